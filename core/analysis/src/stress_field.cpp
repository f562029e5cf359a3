/// Representative-sphere stress fields, their interpolation onto a plane, and σ1 trajectories
/// (stress_field.hpp). Sections: 1. representative spheres; 2. plane interpolation;
/// 3. trajectories.
#include "granular/stress_field.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "granular/error.hpp"
#include "granular/geometry.hpp"
#include "granular/principal.hpp"
#include "granular/spline.hpp"

namespace granular {

// ---- 1. Representative spheres ------------------------------------------------------------

RepresentativeStress representativeSphereStress(const Simulation& sim, const Vec3& boxMin,
                                                const Vec3& boxMax, std::array<int, 3> cells,
                                                double radius) {
  if (!(radius > 0) || cells[0] < 1 || cells[1] < 1 || cells[2] < 1) {
    throw ConfigError("representative spheres: need radius > 0 and at least one cell per axis");
  }
  RepresentativeStress out;
  out.radius = radius;
  const Vec3 size = boxMax - boxMin;
  out.grid.counts = cells;
  out.grid.spacing = Vec3(size.x() / cells[0], size.y() / cells[1], size.z() / cells[2]);
  out.grid.origin = boxMin + 0.5 * out.grid.spacing;
  const std::size_t n = out.grid.size();
  out.stress.assign(n, Mat3::Zero());
  out.volume.assign(n, 0.0);
  out.solidFraction.assign(n, 0.0);
  out.members.assign(n, 0);

  // Per particle: Σ F⊗l over its contacts, and its volume less half of each lens it shares.
  const Particles& p = sim.particles();
  std::vector<Mat3> moment(p.size(), Mat3::Zero());
  std::vector<double> material(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    material[i] = 4.0 / 3.0 * std::numbers::pi * std::pow(p.radius[i], 3);
  }
  sim.forEachContact([&](const ContactView& c) {
    moment[c.particle] += c.force * (c.point - p.position[c.particle]).transpose();
    if (!c.isWall()) {
      const std::size_t j = c.otherParticle();
      const double d = (p.position[j] - p.position[c.particle]).norm();
      material[c.particle] -= 0.5 * lensVolume(p.radius[c.particle], p.radius[j], d);
    }
  });

  // Each particle adds to every sphere containing its centre; the spheres' reach in cells.
  const double r2 = radius * radius;
  std::array<int, 3> reach;
  for (int a = 0; a < 3; ++a) reach[a] = static_cast<int>(std::ceil(radius / out.grid.spacing[a]));
  std::vector<double> materialSum(n, 0.0);
  for (std::size_t q = 0; q < p.size(); ++q) {
    std::array<int, 3> lo, hi;
    for (int a = 0; a < 3; ++a) {
      const int c =
          static_cast<int>(std::floor((p.position[q][a] - boxMin[a]) / out.grid.spacing[a]));
      lo[a] = std::max(0, c - reach[a]);
      hi[a] = std::min(cells[a] - 1, c + reach[a]);
    }
    for (int k = lo[2]; k <= hi[2]; ++k) {
      for (int j = lo[1]; j <= hi[1]; ++j) {
        for (int i = lo[0]; i <= hi[0]; ++i) {
          if ((p.position[q] - out.grid.node(i, j, k)).squaredNorm() >= r2) continue;
          const std::size_t s = out.grid.index(i, j, k);
          out.stress[s] += moment[q];
          materialSum[s] += material[q];
          ++out.members[s];
        }
      }
    }
  }
  for (int k = 0; k < cells[2]; ++k) {
    for (int j = 0; j < cells[1]; ++j) {
      for (int i = 0; i < cells[0]; ++i) {
        const std::size_t s = out.grid.index(i, j, k);
        out.volume[s] = sphereBoxVolume(out.grid.node(i, j, k), radius, boxMin, boxMax);
        out.stress[s] /= out.volume[s];
        out.solidFraction[s] = materialSum[s] / out.volume[s];
      }
    }
  }
  return out;
}

std::vector<double> component(const std::vector<Mat3>& field, int row, int col) {
  std::vector<double> values(field.size());
  for (std::size_t s = 0; s < field.size(); ++s) values[s] = field[s](row, col);
  return values;
}

// ---- 2. Plane interpolation ---------------------------------------------------------------

PlaneField interpolateOnPlane(const RepresentativeStress& field, double y, double xMin, double xMax,
                              double zMin, double zMax, int nx, int nz) {
  if (nx < 2 || nz < 2) throw ConfigError("interpolateOnPlane: need at least 2×2 samples");
  PlaneField plane{xMin, xMax, zMin, zMax, y, nx, nz, {}};
  plane.stress.assign(std::size_t(nx) * nz, Mat3::Zero());
  for (int row = 0; row < 3; ++row) {
    for (int col = 0; col < 3; ++col) {
      const TricubicSpline spline(field.grid.origin, field.grid.spacing, field.grid.counts,
                                  component(field.stress, row, col));
      for (int k = 0; k < nz; ++k) {
        for (int i = 0; i < nx; ++i) {
          plane.stress[std::size_t(k) * nx + i](row, col) = spline(plane.point(i, k));
        }
      }
    }
  }
  return plane;
}

// ---- 3. Trajectories ----------------------------------------------------------------------

namespace {

/// Bilinear interpolation of the plane's tensors at (x, z); nullopt outside the rectangle.
std::optional<Mat3> sample(const PlaneField& plane, double x, double z) {
  const double u = (x - plane.xMin) / (plane.xMax - plane.xMin) * (plane.nx - 1);
  const double v = (z - plane.zMin) / (plane.zMax - plane.zMin) * (plane.nz - 1);
  if (!(u >= 0 && v >= 0 && u <= plane.nx - 1 && v <= plane.nz - 1)) return std::nullopt;
  const int i = std::min(static_cast<int>(u), plane.nx - 2);
  const int k = std::min(static_cast<int>(v), plane.nz - 2);
  const double fu = u - i, fv = v - k;
  auto at = [&](int a, int b) { return plane.stress[std::size_t(b) * plane.nx + a]; };
  return (1 - fu) * (1 - fv) * at(i, k) + fu * (1 - fv) * at(i + 1, k) +
         (1 - fu) * fv * at(i, k + 1) + fu * fv * at(i + 1, k + 1);
}

}  // namespace

std::optional<Vec3> inPlaneSigma1(const Mat3& s, double minAnisotropy) {
  // The symmetric 2×2 in-plane tensor [[a, c], [c, b]] with a = σ11, b = σ33, c = (σ13+σ31)/2.
  const double a = s(0, 0), b = s(2, 2), c = 0.5 * (s(0, 2) + s(2, 0));
  const double mean = 0.5 * (a + b), radius = std::hypot(0.5 * (a - b), c);
  if (!(2.0 * radius >= minAnisotropy * std::abs(mean)) || radius == 0.0) return std::nullopt;
  // σ1 = mean − radius (the most compressive); its direction at angle θ from x with
  // tan 2θ = 2c/(a − b), shifted by a right angle to the smaller eigenvalue.
  const double theta = 0.5 * std::atan2(2.0 * c, a - b) + 0.5 * std::numbers::pi;
  return Vec3(std::cos(theta), 0.0, std::sin(theta));
}

std::vector<std::vector<Vec3>> principalTrajectories(const PlaneField& plane,
                                                     const std::vector<Vec3>& starts, double step,
                                                     const Vec3& heading, double minAnisotropy) {
  auto direction = [&](const Vec3& r) -> std::optional<Vec3> {
    const auto s = sample(plane, r.x(), r.z());
    if (!s) return std::nullopt;
    return inPlaneSigma1(*s, minAnisotropy);
  };
  const Vec3 lo(plane.xMin, plane.y, plane.zMin), hi(plane.xMax, plane.y, plane.zMax);
  const int maxSteps =
      static_cast<int>(4.0 * ((plane.xMax - plane.xMin) + (plane.zMax - plane.zMin)) / step);
  std::vector<std::vector<Vec3>> lines;
  for (const Vec3& start : starts) {
    std::vector<Vec3> line = traceTrajectory(direction, start, step, maxSteps, lo, hi, heading);
    if (line.size() >= 2) lines.push_back(std::move(line));
  }
  return lines;
}

}  // namespace granular
