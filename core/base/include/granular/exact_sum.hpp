#pragma once
/// An exact sum of doubles whose result does not depend on the order of the terms: a long
/// fixed-point accumulator (Kulisch) that covers every finite double, 2^-1074 to 2^1024, in
/// 32-bit limbs, rounded to the nearest double (ties to even) only when read. Sums that cross
/// threads or MPI ranks add their partial accumulators (merge) and so give the same bits for
/// any split of the terms (docs/physics.md §2.9).
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>

namespace granular {

class ExactSum {
 public:
  /// Adds x exactly. Infinities and NaN are remembered: the result is then NaN, +∞ or −∞ as
  /// IEEE addition of the same terms in any order would give.
  /// Inline: the force pass adds a few terms a particle.
  void add(double x) {
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const unsigned biased = unsigned(bits >> 52) & 0x7ffu;
    if (biased == 0x7ffu) {
      addSpecial(x);
      return;
    }
    // x = ± mantissa · 2^(position − 1074): a subnormal's (biased 0) mantissa at bit 0, a
    // normal one's with its hidden bit, one binade up per biased exponent above 1.
    const std::uint64_t normal = biased != 0 ? 1 : 0;
    const std::uint64_t mantissa = (bits & ((std::uint64_t(1) << 52) - 1)) | (normal << 52);
    const unsigned position = biased - unsigned(normal);
    const unsigned shift = position % 32;
    // mantissa << shift spans at most 53 + 31 = 84 bits: three limbs from limb position / 32
    // (≤ 63, so ≤ 65 < kLimbs). Branch-free: a sign mask (0 or −1) negates the parts.
    const std::uint64_t low = mantissa << shift;
    const std::uint64_t high = (mantissa >> 1) >> (63 - shift);
    const std::int64_t sign = -std::int64_t(bits >> 63);
    std::int64_t* limb = limb_.data() + position / 32;
    limb[0] += (std::int64_t(low & 0xffffffffu) ^ sign) - sign;
    limb[1] += (std::int64_t(low >> 32) ^ sign) - sign;
    limb[2] += (std::int64_t(high) ^ sign) - sign;
    if (++pending_ >= kCarryEvery) carry();
  }
  /// Adds x[0], …, x[count − 1] exactly: the same accumulator as adding each, at a fraction of
  /// the cost for a batch of terms of like size (split into three parts on a grid set by the
  /// batch's largest term, each part summed exactly in double; exact_sum.cpp says why exact).
  void addAll(const double* x, std::size_t count);
  /// Adds another accumulator's terms (exactly, in any order).
  void merge(const ExactSum& other);
  /// The sum rounded once to the nearest double (ties to even); ±∞ beyond the largest double.
  double value() const;
  /// True when no term was added or every term cancelled exactly.
  bool isZero() const;

  /// The accumulator's words, for sending between processes: the limbs, carried (each in
  /// [0, 2^32) but the top one, which holds the sign), the count of terms since the last carry
  /// (0), then the special-value flags. The words of k accumulators may be summed element by
  /// element (limbs and count; k < 2^30) with the flags ORed: fromWords of that is their merge,
  /// which is what an MPI reduction of integers does.
  static constexpr int kLimbs = 67;  ///< 67 × 32 bits ≥ 1074 + 1024 + headroom for carries
  using Words = std::array<std::int64_t, kLimbs + 2>;
  Words words() const;
  static ExactSum fromWords(const Words& words);

 private:
  /// A limb holds a signed 64-bit value; each addition adds less than 2^32 to it, so 2^30
  /// additions (and as many merges of carried accumulators) fit before a carry is needed.
  static constexpr std::int64_t kCarryEvery = std::int64_t(1) << 30;
  void addSpecial(double x);  ///< remembers ±∞ or NaN
  void carry();  ///< propagates carries so that every limb but the last lies in [0, 2^32)
  std::array<std::int64_t, kLimbs> limb_{};  ///< limb k weighs 2^(32k − 1074)
  std::int64_t pending_ = 0;  ///< additions since the last carry (each adds < 2^32 a limb)
  std::int64_t special_ = 0;  ///< bits: 1 +∞ seen, 2 −∞ seen, 4 NaN seen
};

}  // namespace granular
