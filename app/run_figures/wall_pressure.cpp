/// wall_pressure.hpp.
#include "wall_pressure.hpp"

#include <algorithm>
#include <cmath>

namespace granular::app {

namespace {

/// The part of a polygon on one side of the height `z` (Sutherland-Hodgman): above it with
/// `keepAbove`, else below.
std::vector<Vec3> clipAt(const std::vector<Vec3>& polygon, double z, bool keepAbove) {
  std::vector<Vec3> out;
  auto inside = [&](const Vec3& x) { return keepAbove ? x.z() >= z : x.z() <= z; };
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vec3 &a = polygon[k], &b = polygon[(k + 1) % polygon.size()];
    if (inside(a)) out.push_back(a);
    if (inside(a) != inside(b)) out.push_back(a + (z - a.z()) / (b.z() - a.z()) * (b - a));
  }
  return out;
}

double area(const std::vector<Vec3>& polygon) {
  Vec3 twice = Vec3::Zero();
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    twice += polygon[k].cross(polygon[(k + 1) % polygon.size()]);
  }
  return 0.5 * twice.norm();
}

}  // namespace

double areaBetween(const std::vector<Vec3>& polygon, double zLow, double zHigh) {
  const std::vector<Vec3> above = clipAt(polygon, zLow, true);
  return above.size() < 3 ? 0.0 : area(clipAt(above, zHigh, false));
}

std::vector<PressureBand> pressureProfile(const WallCells& wall, const WallContacts& contacts,
                                          double bandHeight) {
  double lo = HUGE_VAL, hi = -HUGE_VAL;
  for (const auto& cell : wall.cells) {
    for (const Vec3& x : cell) lo = std::min(lo, x.z()), hi = std::max(hi, x.z());
  }
  if (wall.cells.empty() || !(bandHeight > 0)) return {};
  const bool flat = hi - lo < 1e-3 * bandHeight;
  const int bands = flat ? 1 : std::clamp(int(std::ceil((hi - lo) / bandHeight)), 1, 200);
  const double height = flat ? 0.0 : (hi - lo) / bands;
  std::vector<PressureBand> profile(static_cast<std::size_t>(bands));
  std::vector<double> areas(profile.size(), 0.0), forces(profile.size(), 0.0);
  for (int b = 0; b < bands; ++b) {
    profile[b].z = flat ? 0.5 * (lo + hi) : lo + (b + 0.5) * height;
    for (const auto& cell : wall.cells) {
      areas[b] += flat ? area(cell) : areaBetween(cell, lo + b * height, lo + (b + 1) * height);
    }
  }
  for (std::size_t c = 0; c < contacts.z.size(); ++c) {
    // A contact point lies in the overlap, up to a particle's overlap beyond the wall's ends.
    const int b =
        flat ? 0 : std::clamp(int(std::floor((contacts.z[c] - lo) / height)), 0, bands - 1);
    forces[b] += contacts.force[c];
    ++profile[b].contacts;
  }
  std::vector<PressureBand> kept;
  for (std::size_t b = 0; b < profile.size(); ++b) {
    if (!(areas[b] > 0.0)) continue;
    profile[b].pressure = forces[b] / areas[b];
    kept.push_back(profile[b]);
  }
  return kept;
}

}  // namespace granular::app
