/// Not-a-knot cubic splines on regular grids (spline.hpp).
#include "granular/spline.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "granular/error.hpp"

namespace granular {

void notAKnotSecondDerivatives(std::span<const double> values, double spacing,
                               std::span<double> second) {
  if (second.size() != values.size())
    throw ConfigError("notAKnotSecondDerivatives: output size differs from input size");
  if (!(spacing > 0) || !std::isfinite(spacing))
    throw ConfigError("notAKnotSecondDerivatives: spacing must be > 0");
  const std::size_t n = values.size();
  const double invH2 = 1.0 / (spacing * spacing);
  auto secondDifference = [&](std::size_t i) {
    return (values[i - 1] - 2.0 * values[i] + values[i + 1]) * invH2;
  };
  if (n <= 2) {
    std::fill(second.begin(), second.end(), 0.0);
    return;
  }
  if (n == 3) {
    std::fill(second.begin(), second.end(), secondDifference(1));
    return;
  }
  // Row i: M_{i-1} + 4 M_i + M_{i+1} = 6 Δ²y_i / h². With M0 = 2M1 − M2 (not-a-knot) row 1
  // reads 6 M1 = 6 Δ²y_1 / h²; the same at the other end.
  second[1] = secondDifference(1);
  second[n - 2] = secondDifference(n - 2);
  // Rows 2 … n − 3 with M1 and M_{n−2} known: Thomas algorithm on diag 4, off-diagonals 1.
  // second[] holds the modified right-hand sides d'_i during the forward sweep, cp the modified
  // super-diagonal c'_i = 1/(4 − c'_{i−1}); then M_i = d'_i − c'_i M_{i+1} backwards.
  if (n >= 5) {
    const std::size_t first = 2, last = n - 3;
    double cPrime = 0;  // c'_{i−1}
    std::vector<double> cp(last - first + 1);
    for (std::size_t i = first; i <= last; ++i) {
      double rhs = 6.0 * secondDifference(i);
      if (i == first) rhs -= second[1];
      if (i == last) rhs -= second[n - 2];
      const double denom = 4.0 - (i == first ? 0.0 : cPrime);
      const double prev = i == first ? 0.0 : second[i - 1];
      second[i] = (rhs - prev) / denom;
      cPrime = 1.0 / denom;
      cp[i - first] = cPrime;
    }
    for (std::size_t i = last; i-- > first;) second[i] -= cp[i - first] * second[i + 1];
  }
  second[0] = 2.0 * second[1] - second[2];
  second[n - 1] = 2.0 * second[n - 2] - second[n - 3];
}

SplineWeights splineWeights(double x, double origin, double spacing, int count) {
  SplineWeights w;
  if (count <= 1) {
    w.a = 1.0;
    return w;
  }
  const double u = (x - origin) / spacing;
  // Clamp the interval, not t: outside the nodes the end cubic continues (extrapolation).
  // Written so that NaN (and anything beyond int's range) never reaches the cast.
  const double fl = std::floor(u);
  const int i = fl >= count - 2 ? count - 2 : (fl >= 0 ? static_cast<int>(fl) : 0);
  const double t = u - i, s = 1.0 - t;
  const double h2 = spacing * spacing / 6.0;
  w.lower = i;
  w.upper = i + 1;
  w.a = s;
  w.b = t;
  w.c = h2 * (s * s * s - s);
  w.d = h2 * (t * t * t - t);
  return w;
}

CubicSpline::CubicSpline(double origin, double spacing, std::vector<double> values)
    : origin_(origin), spacing_(spacing), values_(std::move(values)) {
  if (values_.empty()) throw ConfigError("CubicSpline: needs at least one value");
  if (!std::isfinite(origin_)) throw ConfigError("CubicSpline: origin must be finite");
  second_.resize(values_.size());
  notAKnotSecondDerivatives(values_, spacing_, second_);
}

double CubicSpline::operator()(double x) const {
  const SplineWeights w = splineWeights(x, origin_, spacing_, count());
  return w.a * values_[w.lower] + w.b * values_[w.upper] + w.c * second_[w.lower] +
         w.d * second_[w.upper];
}

TricubicSpline::TricubicSpline(const Vec3& origin, const Vec3& spacing, std::array<int, 3> counts,
                               std::vector<double> values)
    : origin_(origin), spacing_(spacing), counts_(counts) {
  std::size_t total = 1;
  for (int k = 0; k < 3; ++k) {
    if (counts_[k] < 1) throw ConfigError("TricubicSpline: counts must be >= 1 per axis");
    if (!(spacing_[k] > 0) || !std::isfinite(spacing_[k]))
      throw ConfigError("TricubicSpline: spacing must be > 0 per axis");
    total *= static_cast<std::size_t>(counts_[k]);
  }
  if (!origin_.allFinite()) throw ConfigError("TricubicSpline: origin must be finite");
  if (values.size() != total) {
    std::string message = "TricubicSpline: ";
    message += std::to_string(values.size());
    message += " values for ";
    message += std::to_string(total);
    message += " nodes";
    throw ConfigError(message);
  }

  nodes_.resize(total);
  for (std::size_t n = 0; n < total; ++n) nodes_[n][0] = values[n];
  // Mask m is L along the lowest set bit's axis applied to mask m without that bit, which is
  // smaller and so already done: L_x f, L_y f, L_xL_y f, L_z f, L_xL_z f, L_yL_z f, L_xL_yL_z f.
  const std::array<std::size_t, 3> stride = {1, static_cast<std::size_t>(counts_[0]),
                                             static_cast<std::size_t>(counts_[0] * counts_[1])};
  std::vector<double> line, second;
  for (int mask = 1; mask < 8; ++mask) {
    const int axis = mask & 1 ? 0 : (mask & 2 ? 1 : 2);
    const int source = mask & ~(1 << axis);
    const std::size_t n = static_cast<std::size_t>(counts_[axis]);
    line.resize(n);
    second.resize(n);
    // Every line along `axis`: the nodes whose index along it is 0.
    for (std::size_t start = 0; start < total; ++start) {
      if ((start / stride[axis]) % n != 0) continue;
      for (std::size_t i = 0; i < n; ++i) line[i] = nodes_[start + i * stride[axis]][source];
      notAKnotSecondDerivatives(line, spacing_[axis], second);
      for (std::size_t i = 0; i < n; ++i) nodes_[start + i * stride[axis]][mask] = second[i];
    }
  }
}

double TricubicSpline::operator()(const Vec3& p) const {
  const SplineWeights wx = splineWeights(p.x(), origin_.x(), spacing_.x(), counts_[0]);
  const SplineWeights wy = splineWeights(p.y(), origin_.y(), spacing_.y(), counts_[1]);
  const SplineWeights wz = splineWeights(p.z(), origin_.z(), spacing_.z(), counts_[2]);
  // Per axis and corner (lower, upper): the weight of the value and of the second derivative.
  const double ax[2][2] = {{wx.a, wx.c}, {wx.b, wx.d}};
  const double ay[2][2] = {{wy.a, wy.c}, {wy.b, wy.d}};
  const double az[2][2] = {{wz.a, wz.c}, {wz.b, wz.d}};
  const int ix[2] = {wx.lower, wx.upper}, iy[2] = {wy.lower, wy.upper},
            iz[2] = {wz.lower, wz.upper};
  const std::size_t nx = static_cast<std::size_t>(counts_[0]);
  const std::size_t nxy = nx * static_cast<std::size_t>(counts_[1]);
  double sum = 0;
  for (int cz = 0; cz < 2; ++cz) {
    for (int cy = 0; cy < 2; ++cy) {
      const std::size_t row =
          static_cast<std::size_t>(iz[cz]) * nxy + static_cast<std::size_t>(iy[cy]) * nx;
      for (int cx = 0; cx < 2; ++cx) {
        const std::array<double, 8>& q = nodes_[row + static_cast<std::size_t>(ix[cx])];
        // Contract x first, then y, then z: 14 multiplications instead of 24 for this corner.
        double byZ[2];
        for (int bz = 0; bz < 2; ++bz) {
          const double y0 = ax[cx][0] * q[bz * 4 + 0] + ax[cx][1] * q[bz * 4 + 1];
          const double y1 = ax[cx][0] * q[bz * 4 + 2] + ax[cx][1] * q[bz * 4 + 3];
          byZ[bz] = ay[cy][0] * y0 + ay[cy][1] * y1;
        }
        sum += az[cz][0] * byZ[0] + az[cz][1] * byZ[1];
      }
    }
  }
  return sum;
}

}  // namespace granular
