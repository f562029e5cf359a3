/// The long accumulator (granular/exact_sum.hpp).
#include "granular/exact_sum.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

#include "granular/simd_build.hpp"

namespace granular {
namespace {

constexpr int kOffset = 1074;  // bit 0 of limb 0 weighs 2^-1074, the smallest subnormal

unsigned biasedExponent(double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  return unsigned(bits >> 52) & 0x7ffu;
}

}  // namespace

void ExactSum::addSpecial(double x) {
  special_ |= std::isnan(x) ? 4 : (x > 0 ? 1 : 2);
}

namespace {

/// Four doubles: one register under AVX2, two under SSE2.
typedef double Lanes __attribute__((vector_size(32)));
typedef std::int64_t LaneMask __attribute__((vector_size(32)));

/// One step of splitFour: the three parts of the four terms at x added to `part`, and whether
/// any leaves a remainder (`left`).
inline void splitStep(const double* x, const Lanes& v1, const Lanes& v2, const Lanes& v3,
                      Lanes (&part)[3], LaneMask& left) {
  Lanes r;
  std::memcpy(&r, x, sizeof r);
  Lanes q = (v1 + r) - v1;
  r -= q;
  part[0] += q;
  q = (v2 + r) - v2;
  r -= q;
  part[1] += q;
  q = (v3 + r) - v3;
  r -= q;
  part[2] += q;
  const Lanes zero = {};
  left |= r != zero;
}

/// The largest |x| of x[0, m) (m a multiple of 4; NaN is passed over), four at a time.
#define GRANULAR_LARGEST_BODY              \
  Lanes largest = {};                      \
  for (std::size_t i = 0; i < m; i += 4) { \
    Lanes r;                               \
    std::memcpy(&r, x + i, sizeof r);      \
    r = r < 0 ? -r : r;                    \
    largest = r > largest ? r : largest;   \
  }                                        \
  return std::max(std::max(largest[0], largest[1]), std::max(largest[2], largest[3]));

double largestMagnitude(const double* x, std::size_t m) {
  GRANULAR_LARGEST_BODY
}

[[gnu::target("avx2")]] double largestMagnitudeAvx2(const double* x, std::size_t m) {
  GRANULAR_LARGEST_BODY
}

#undef GRANULAR_LARGEST_BODY

/// Adds the three parts of x[0, m) (m a multiple of 8) on the grids of c1, c2, c3 (addAll) to
/// `part`, four terms at a time in two interleaved chains; true when some term leaves a
/// remainder below the third grid. Compiled twice: for any x86-64 and for AVX2.
#define GRANULAR_SPLIT_FOUR_BODY                                                   \
  const Lanes v1 = {c1, c1, c1, c1}, v2 = {c2, c2, c2, c2}, v3 = {c3, c3, c3, c3}; \
  Lanes other[3] = {};                                                             \
  LaneMask left = {};                                                              \
  for (std::size_t i = 0; i < m; i += 8) {                                         \
    splitStep(x + i, v1, v2, v3, part, left);                                      \
    splitStep(x + i + 4, v1, v2, v3, other, left);                                 \
  }                                                                                \
  for (int j = 0; j < 3; ++j) part[j] += other[j];                                 \
  return (left[0] | left[1] | left[2] | left[3]) != 0;

bool splitFour(const double* x, std::size_t m, double c1, double c2, double c3, Lanes (&part)[3]) {
  GRANULAR_SPLIT_FOUR_BODY
}

[[gnu::target("avx2")]] bool splitFourAvx2(const double* x, std::size_t m, double c1, double c2,
                                           double c3, Lanes (&part)[3]) {
  GRANULAR_SPLIT_FOUR_BODY
}

#undef GRANULAR_SPLIT_FOUR_BODY

/// 1.5 · 2^e for a normal result.
double threeHalves(int e) {
  const std::uint64_t bits = (std::uint64_t(e + 1023) << 52) | (std::uint64_t(1) << 51);
  double x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

/// x's remainder below the third grid (addAll).
double remainder(double x, double c1, double c2, double c3) {
  x -= (c1 + x) - c1;
  x -= (c2 + x) - c2;
  return x - ((c3 + x) - c3);
}

}  // namespace

// The batch's largest term has biased exponent top: every |x| < 2^(T+1), T = top − 1023. On the
// grids g_j = 2^(T+1−40j), j = 1, 2, 3, a term splits exactly as x = q1 + q2 + q3 + r:
//   q_j = (C_j + r) − C_j with C_j = 1.5·2^52·g_j rounds the remainder r to a multiple of g_j
//   exactly, because C_j + r stays in [2^52 g_j, 2^53 g_j), where doubles are g_j apart
//   (|r| < 2^40 g_j: the term itself at j = 1, then |r| ≤ g_{j−1}/2 = 2^39 g_j);
//   r − q_j is exact (it has no more significant bits than r).
// Each part is a multiple of its grid below 2^40 g_j, so up to 2^12 of them sum exactly in
// double (the multiples of g_j below 2^53 g_j are all doubles): two sets of four lanes of at most
// 129 terms each, then the lanes and the sets (each sum below 2^51 g_j: exact). What is left below
// the third grid (terms more than about 70 binades under the largest) is added one by one. The
// three part sums are then added as any term. Where the grids would leave the double range (C_1
// overflowing, g_3 subnormal) and for infinities and NaN, every term is added alone.
void ExactSum::addAll(const double* x, std::size_t count) {
  constexpr std::size_t kBatch = 1024;
  const bool avx2 = simdBuild() == SimdBuild::Avx2;  // the process's one choice
  for (std::size_t start = 0; start < count; start += kBatch) {
    const std::size_t m = std::min(kBatch, count - start);
    const double* batch = x + start;
    // The tail beyond the last whole eight goes through the same loops, padded with zeros
    // (which split into zeros).
    const std::size_t whole = m - m % 8;
    double tail[8] = {};
    std::copy(batch + whole, batch + m, tail);
    auto largestOf = avx2 ? largestMagnitudeAvx2 : largestMagnitude;
    const unsigned top = biasedExponent(std::max(largestOf(batch, whole), largestOf(tail, 8)));
    if (top < 200 || top > 2000) {  // tiny, huge or not finite: one by one
      for (std::size_t i = 0; i < m; ++i) add(batch[i]);
      continue;
    }
    const int t = int(top) - 1023;
    const double c1 = threeHalves(t + 13), c2 = threeHalves(t - 27), c3 = threeHalves(t - 67);
    Lanes part[3] = {};
    auto split = avx2 ? splitFourAvx2 : splitFour;
    const bool body = split(batch, whole, c1, c2, c3, part);
    const bool leftOver = split(tail, 8, c1, c2, c3, part) || body;
    if (leftOver) {
      for (std::size_t i = 0; i < m; ++i) {
        const double r = remainder(batch[i], c1, c2, c3);
        if (r != 0.0) add(r);
      }
    }
    for (const Lanes& lanes : part) add((lanes[0] + lanes[1]) + (lanes[2] + lanes[3]));
  }
}

void ExactSum::merge(const ExactSum& other) {
  ExactSum o = other;
  o.carry();
  carry();
  for (int i = 0; i < kLimbs; ++i) limb_[i] += o.limb_[i];
  pending_ = 1;
  special_ |= o.special_;
}

void ExactSum::carry() {
  for (int i = 0; i + 1 < kLimbs; ++i) {
    const std::int64_t low = limb_[i] & 0xffffffff;  // in [0, 2^32), also for negative limbs
    limb_[i + 1] += (limb_[i] - low) / (std::int64_t(1) << 32);
    limb_[i] = low;
  }
  pending_ = 0;
}

bool ExactSum::isZero() const {
  ExactSum c = *this;
  c.carry();
  for (std::int64_t l : c.limb_) {
    if (l != 0) return false;
  }
  return true;
}

double ExactSum::value() const {
  if ((special_ & 4) != 0 || (special_ & 3) == 3) return std::numeric_limits<double>::quiet_NaN();
  if ((special_ & 1) != 0) return std::numeric_limits<double>::infinity();
  if ((special_ & 2) != 0) return -std::numeric_limits<double>::infinity();
  ExactSum c = *this;
  c.carry();
  // The top limb carries the sign; a negative sum is negated limb by limb (two's complement
  // over the whole accumulator: complement, then add one with carries).
  const bool negative = c.limb_[kLimbs - 1] < 0;
  if (negative) {
    for (std::int64_t& l : c.limb_) l = -l;
    c.carry();
  }
  int top = kLimbs - 1;
  while (top >= 0 && c.limb_[top] == 0) --top;
  if (top < 0) return 0.0;
  // The magnitude's top 64 bits, with every bit below them folded into the lowest (sticky):
  // converting that integer to double rounds to nearest even exactly as the full value would.
  unsigned __int128 window = 0;
  int low = top - 2;  // the three top limbs: 96 bits, at least 65 of them significant
  for (int i = top; i >= low; --i) {
    window = (window << 32) | std::uint64_t(i >= 0 ? c.limb_[i] : 0);
  }
  bool sticky = false;
  for (int i = low - 1; i >= 0; --i) sticky = sticky || c.limb_[i] != 0;
  const int length =
      128 - (std::uint64_t(window >> 64) != 0 ? std::countl_zero(std::uint64_t(window >> 64))
                                              : 64 + std::countl_zero(std::uint64_t(window)));
  const int drop = length > 64 ? length - 64 : 0;
  if (drop > 0) {
    sticky = sticky || (window & ((static_cast<unsigned __int128>(1) << drop) - 1)) != 0;
    window >>= drop;
  }
  std::uint64_t top64 = std::uint64_t(window);
  if (sticky) top64 |= 1;  // below the 53 kept bits by 11: it only breaks ties
  // Subnormal results would round twice (to 64 bits here, to the subnormal grid in ldexp): a
  // sum below 2^-1022 has its whole value within the two bottom limbs and the window, exact.
  const int exponent = 32 * low - kOffset + drop;
  const double magnitude = std::ldexp(static_cast<double>(top64), exponent);
  return negative ? -magnitude : magnitude;
}

ExactSum::Words ExactSum::words() const {
  ExactSum c = *this;
  c.carry();
  Words w{};
  for (int i = 0; i < kLimbs; ++i) w[i] = c.limb_[i];
  w[kLimbs] = c.pending_;
  w[kLimbs + 1] = special_;
  return w;
}

ExactSum ExactSum::fromWords(const Words& w) {
  ExactSum s;
  for (int i = 0; i < kLimbs; ++i) s.limb_[i] = w[i];
  s.pending_ = w[kLimbs];
  s.special_ = w[kLimbs + 1];
  return s;
}

}  // namespace granular
