#pragma once
/// A uniform draw in [0, 1) from one 64-bit Mersenne Twister draw (private to the core): the
/// particles a seed generates or inserts are the same with every standard library, which
/// std::uniform_real_distribution, whose algorithm the standard leaves open, does not promise.
#include <random>

namespace granular {

/// The top 53 bits of one draw, exact in a double.
inline double unitUniform(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

}  // namespace granular
