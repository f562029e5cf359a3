/// The order-independent exact sum (granular/exact_sum.hpp), the reduction that lets sums which
/// cross threads or processes give the same bits for any split: exactness against integer
/// arithmetic, rounding once to nearest-even, cancellations a naive sum loses, subnormals,
/// overflow and the special values, and the same bits for every order and every split.
#include "granular/exact_sum.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <tuple>
#include <utility>
#include <vector>

using namespace granular;

namespace {

std::uint64_t bitsOf(double x) {
  std::uint64_t b;
  std::memcpy(&b, &x, sizeof b);
  return b;
}

double sumOf(const std::vector<double>& xs) {
  ExactSum s;
  for (double x : xs) s.add(x);
  return s.value();
}

}  // namespace

TEST(ExactSum, MatchesIntegerArithmeticRoundedOnce) {
  // Terms k · 2^-30 with |k| < 2^53 are exact doubles and their sum is exact in 128-bit
  // integers; converting that integer to double rounds once, to nearest even.
  std::mt19937_64 random(7);
  for (int trial = 0; trial < 50; ++trial) {
    std::vector<double> xs;
    __int128 exact = 0;
    for (int i = 0; i < 1000; ++i) {
      const std::int64_t k =
          std::int64_t(random() >> 11) * ((random() & 1) != 0 ? 1 : -1);  // |k| < 2^53
      xs.push_back(std::ldexp(double(k), -30));
      exact += k;
    }
    const double expected = std::ldexp(static_cast<double>(exact), -30);
    EXPECT_EQ(bitsOf(sumOf(xs)), bitsOf(expected)) << trial;
  }
}

TEST(ExactSum, KeepsWhatANaiveSumLosesAndRoundsTiesToEven) {
  EXPECT_EQ(sumOf({1e308, 1.0, -1e308}), 1.0);  // naive: 0
  EXPECT_EQ(sumOf({1.0, 1e100, 1.0, -1e100}), 2.0);
  const double big = std::ldexp(1.0, 53);
  EXPECT_EQ(sumOf({big, 1.0}), big);                               // a tie: to even
  EXPECT_EQ(sumOf({big, 1.0, std::ldexp(1.0, -100)}), big + 2.0);  // just above the tie
  EXPECT_EQ(sumOf({big + 2.0, 1.0}), big + 4.0);                   // a tie from odd: up
  EXPECT_EQ(sumOf({DBL_MAX, DBL_MAX, -DBL_MAX}), DBL_MAX);         // exact through 2^1025
  EXPECT_EQ(sumOf({DBL_MAX, DBL_MAX}), std::numeric_limits<double>::infinity());
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(sumOf({tiny, tiny, tiny}), 3 * tiny);
  EXPECT_EQ(sumOf({DBL_MIN, -tiny}), DBL_MIN - tiny);  // normal minus subnormal, exact
  EXPECT_EQ(sumOf({1.0, -1.0}), 0.0);
  EXPECT_TRUE(ExactSum().isZero());
  EXPECT_EQ(sumOf({-3.5, 1.25}), -2.25);
}

TEST(ExactSum, SpecialValuesAsIeeeAdditionWouldGive) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(sumOf({1.0, inf, 5.0}), inf);
  EXPECT_EQ(sumOf({-inf, 1.0}), -inf);
  EXPECT_TRUE(std::isnan(sumOf({inf, -inf})));
  EXPECT_TRUE(std::isnan(sumOf({1.0, std::numeric_limits<double>::quiet_NaN()})));
}

TEST(ExactSum, TheSameBitsInEveryOrderAndEverySplit) {
  // Terms over 600 binary orders of magnitude, both signs: a naive sum depends on the order;
  // this one never, and partial sums merged in any grouping give the same bits.
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  std::uniform_int_distribution<int> exponent(-300, 300);
  std::vector<double> xs;
  for (int i = 0; i < 5000; ++i) {
    xs.push_back(std::ldexp(mantissa(random), exponent(random)) * ((random() & 1) ? 1 : -1));
  }
  const std::uint64_t reference = bitsOf(sumOf(xs));
  bool naiveDiffers = false;
  double naiveFirst = 0;
  for (double x : xs) naiveFirst += x;
  for (int shuffle = 0; shuffle < 5; ++shuffle) {
    std::shuffle(xs.begin(), xs.end(), random);
    EXPECT_EQ(bitsOf(sumOf(xs)), reference) << shuffle;
    double naive = 0;
    for (double x : xs) naive += x;
    naiveDiffers = naiveDiffers || naive != naiveFirst;
    // Three parts, merged in two groupings, one part sent through its words.
    ExactSum parts[3];
    for (std::size_t i = 0; i < xs.size(); ++i) parts[(i * 7 + shuffle) % 3].add(xs[i]);
    ExactSum a = parts[0];
    a.merge(parts[1]);
    a.merge(ExactSum::fromWords(parts[2].words()));
    ExactSum b = parts[2];
    b.merge(parts[0]);
    b.merge(parts[1]);
    EXPECT_EQ(bitsOf(a.value()), reference) << shuffle;
    EXPECT_EQ(bitsOf(b.value()), reference) << shuffle;
  }
  EXPECT_TRUE(naiveDiffers);  // the test's terms do tell the orders apart
}

namespace {

/// The accumulator's carried words after adding xs one by one, and after addAll of the same.
std::pair<ExactSum::Words, ExactSum::Words> bothWays(const std::vector<double>& xs) {
  ExactSum each, all;
  for (double x : xs) each.add(x);
  all.addAll(xs.data(), xs.size());
  ExactSum::Words a = each.words(), b = all.words();
  a[ExactSum::kLimbs] = b[ExactSum::kLimbs] = 0;  // the count since the last carry: 0 once read
  return {a, b};
}

}  // namespace

TEST(ExactSum, AddAllHoldsExactlyWhatAddingEachHolds) {
  // addAll splits each term on three grids set by the batch's largest; the accumulator must hold
  // the same exact value as term-by-term addition (its carried words equal), for batches of like
  // size (one split each), terms far below the largest (their remainders added one by one),
  // spans wider than the grids reach, subnormal and huge terms (one by one), lengths around
  // the lanes, the unrolling and the 1024-term batches, and both signs.
  std::mt19937_64 random(17);
  std::uniform_real_distribution<double> mantissa(1.0, 2.0);
  const int spans[] = {0, 3, 30, 75, 130, 2000};
  const std::size_t lengths[] = {0, 1, 3, 4, 7, 8, 9, 100, 1023, 1024, 1025, 2049, 5000};
  for (int span : spans) {
    std::uniform_int_distribution<int> exponent(-span / 2, span - span / 2);
    for (std::size_t length : lengths) {
      std::vector<double> xs;
      for (std::size_t i = 0; i < length; ++i) {
        const int e = span == 2000 ? exponent(random) - 60 : exponent(random) - 10;
        xs.push_back(std::ldexp(mantissa(random), std::clamp(e, -1074, 1000)) *
                     ((random() & 1) ? 1 : -1));
      }
      const auto [each, all] = bothWays(xs);
      EXPECT_EQ(each, all) << "span " << span << ", length " << length;
    }
  }
  // Cancellation to exactly zero within a batch, and terms whose parts all land on one grid.
  std::vector<double> cancelling;
  for (int i = 0; i < 600; ++i) {
    const double x = std::ldexp(mantissa(random), (i % 90) - 45);
    cancelling.push_back(x);
    cancelling.push_back(-x);
  }
  std::shuffle(cancelling.begin(), cancelling.end(), random);
  ExactSum zero;
  zero.addAll(cancelling.data(), cancelling.size());
  EXPECT_TRUE(zero.isZero());
  const double tiny = std::numeric_limits<double>::denorm_min();
  EXPECT_EQ(bothWays({tiny, 3 * tiny, DBL_MIN}).first, bothWays({tiny, 3 * tiny, DBL_MIN}).second);
  EXPECT_EQ(bothWays({DBL_MAX, DBL_MAX, -DBL_MAX, 1.0}).first,
            bothWays({DBL_MAX, DBL_MAX, -DBL_MAX, 1.0}).second);
}

TEST(ExactSum, AddAllMeetsSpecialValuesAsAddingEachDoes) {
  const double inf = std::numeric_limits<double>::infinity();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> xs(50, 0.25);
  for (const auto& [at, special, isNan] : {std::tuple{0, inf, false}, std::tuple{17, -inf, false},
                                           std::tuple{49, nan, true}, std::tuple{8, nan, true}}) {
    std::vector<double> ys = xs;
    ys[static_cast<std::size_t>(at)] = special;
    ExactSum s;
    s.addAll(ys.data(), ys.size());
    if (isNan) {
      EXPECT_TRUE(std::isnan(s.value())) << at;
    } else {
      EXPECT_EQ(s.value(), special) << at;
    }
  }
  ExactSum both;
  const double mixed[] = {1.0, inf, 2.0, -inf};
  both.addAll(mixed, 4);
  EXPECT_TRUE(std::isnan(both.value()));
}
