/// The long accumulator (granular/exact_sum.hpp).
#include "granular/exact_sum.hpp"

#include <bit>
#include <cmath>
#include <cstring>
#include <limits>

namespace granular {
namespace {

constexpr int kOffset = 1074;  // bit 0 of limb 0 weighs 2^-1074, the smallest subnormal

}  // namespace

void ExactSum::addSpecial(double x) {
  special_ |= std::isnan(x) ? 4 : (x > 0 ? 1 : 2);
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
