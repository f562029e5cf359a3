#pragma once
/// An exact sum of doubles whose result does not depend on the order of the terms: a long
/// fixed-point accumulator (Kulisch) that covers every finite double, 2^-1074 to 2^1024, in
/// 32-bit limbs, rounded to the nearest double (ties to even) only when read. Sums that cross
/// threads or MPI ranks add their partial accumulators (merge) and so give the same bits for
/// any split of the terms (docs/physics.md §2.9).
#include <array>
#include <cstdint>

namespace granular {

class ExactSum {
 public:
  /// Adds x exactly. Infinities and NaN are remembered: the result is then NaN, +∞ or −∞ as
  /// IEEE addition of the same terms in any order would give.
  void add(double x);
  /// Adds another accumulator's terms (exactly, in any order).
  void merge(const ExactSum& other);
  /// The sum rounded once to the nearest double (ties to even); ±∞ beyond the largest double.
  double value() const;
  /// True when no term was added or every term cancelled exactly.
  bool isZero() const;

  /// The accumulator's words, for sending between processes: limbs, then the count of terms
  /// since the last carry, then the special-value flags.
  static constexpr int kLimbs = 67;  ///< 67 × 32 bits ≥ 1074 + 1024 + headroom for carries
  using Words = std::array<std::int64_t, kLimbs + 2>;
  Words words() const;
  static ExactSum fromWords(const Words& words);

 private:
  void carry();  ///< propagates carries so that every limb but the last lies in [0, 2^32)
  std::array<std::int64_t, kLimbs> limb_{};  ///< limb k weighs 2^(32k − 1074)
  std::int64_t pending_ = 0;  ///< additions since the last carry (each adds < 2^32 a limb)
  std::int64_t special_ = 0;  ///< bits: 1 +∞ seen, 2 −∞ seen, 4 NaN seen
};

}  // namespace granular
