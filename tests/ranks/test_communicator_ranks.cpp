/// The communicator's contract on 1 to 4 MPI ranks: reductions give the same bits on every rank
/// and for any rank count, exchanges deliver what each rank sent.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "granular/bricks.hpp"
#include "ranks.hpp"

using namespace granular;
using granular::testing::world;

namespace {

/// Term k of a fixed sequence: magnitudes over 60 decades, both signs, a few subnormals.
double term(int k) {
  const double mantissa = 1.0 + std::fmod(k * 0.6180339887498949, 1.0);
  const int exponent = (k * 37) % 200 - 100;
  const double x = std::ldexp(mantissa, exponent) * (k % 3 == 0 ? -1.0 : 1.0);
  return k % 997 == 0 ? 1e-310 * (k % 2 ? 1 : -1) : x;
}

}  // namespace

TEST(Ranks, ExactSumsAreTheSameBitsForAnySplitAmongRanks) {
  const Communicator& w = world();
  constexpr int kTerms = 20000;
  ExactSum all;
  for (int k = 0; k < kTerms; ++k) all.add(term(k));
  // Each rank adds a strided share, then a contiguous one: two splits per rank count.
  std::vector<ExactSum> mine(2);
  for (int k = w.rank(); k < kTerms; k += w.size()) mine[0].add(term(k));
  const int begin = kTerms * w.rank() / w.size(), end = kTerms * (w.rank() + 1) / w.size();
  for (int k = begin; k < end; ++k) mine[1].add(term(k));
  w.mergeOverRanks(mine);
  EXPECT_EQ(mine[0].value(), all.value());
  EXPECT_EQ(mine[1].value(), all.value());
  // And a naive double sum of the same terms in order differs: the test can tell.
  double naive = 0.0;
  for (int k = 0; k < kTerms; ++k) naive += term(k);
  EXPECT_NE(naive, all.value());
}

TEST(Ranks, ReductionsAgreeOnEveryRank) {
  const Communicator& w = world();
  const int r = w.rank(), n = w.size();
  EXPECT_EQ(w.maxOverRanks(-1.0 - r), -1.0);
  EXPECT_EQ(w.maxOverRanks(0.5 * r), 0.5 * (n - 1));
  EXPECT_EQ(w.sumOverRanks(std::uint64_t(r + 1)), std::uint64_t(n * (n + 1) / 2));
  EXPECT_FALSE(w.anyOverRanks(false));
  EXPECT_TRUE(w.anyOverRanks(r == n - 1));
}

TEST(Ranks, ExchangeDeliversEachRanksBytesToEachRank) {
  const Communicator& w = world();
  const int r = w.rank(), n = w.size();
  std::vector<std::vector<std::byte>> out(n);
  for (int to = 0; to < n; ++to) {
    for (int k = 0; k < r + 2 * to; ++k) out[to].push_back(std::byte(r * 16 + to + k));
  }
  const std::vector<std::vector<std::byte>> in = w.exchange(out);
  ASSERT_EQ(static_cast<int>(in.size()), n);
  for (int from = 0; from < n; ++from) {
    ASSERT_EQ(static_cast<int>(in[from].size()), from + 2 * r) << "from " << from;
    for (int k = 0; k < from + 2 * r; ++k) EXPECT_EQ(in[from][k], std::byte(from * 16 + r + k));
  }
  std::vector<std::byte> mine(5, std::byte(r + 7));
  EXPECT_EQ(w.broadcast(mine), std::vector<std::byte>(5, std::byte(7)));
}

TEST(Ranks, MergingWithCountsAndSpecialValuesAgreesOnEveryRank) {
  // Sums and counts in one reduction; a special value on one rank reaches every rank's sum as
  // IEEE addition would give it (one rank's +inf: +inf; +inf and -inf on two ranks: NaN).
  const Communicator& w = world();
  const int r = w.rank(), n = w.size();
  std::vector<ExactSum> sums(3);
  sums[0].add(0.25 * (r + 1));
  if (r == n - 1) sums[1].add(std::numeric_limits<double>::infinity());
  sums[1].add(1.0);
  if (r == 0) sums[2].add(std::numeric_limits<double>::infinity());
  if (r == n - 1) sums[2].add(-std::numeric_limits<double>::infinity());
  std::vector<std::uint64_t> counts{std::uint64_t(r + 1), 7};
  w.mergeOverRanks(sums, counts);
  EXPECT_EQ(sums[0].value(), 0.25 * n * (n + 1) / 2);
  EXPECT_EQ(sums[1].value(), std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(sums[2].value()));
  EXPECT_EQ(counts, (std::vector<std::uint64_t>{std::uint64_t(n * (n + 1) / 2), 7u * n}));
}

TEST(Ranks, ExchangeOfKnownSizesDeliversToTheRanksThatExpectIt) {
  // Each rank sends to the next only (a ring: the ghosts' neighbours), r + 3 bytes; the others
  // get nothing and expect nothing, and no message passes between them.
  const Communicator& w = world();
  const int r = w.rank(), n = w.size();
  const int next = (r + 1) % n, previous = (r + n - 1) % n;
  std::vector<std::vector<std::byte>> out(n);
  for (int k = 0; k < r + 3; ++k) out[next].push_back(std::byte(r * 16 + k));
  std::vector<std::size_t> incoming(n, 0);
  incoming[previous] = static_cast<std::size_t>(previous + 3);
  const std::vector<std::vector<std::byte>> in = w.exchangeKnown(out, incoming);
  ASSERT_EQ(static_cast<int>(in.size()), n);
  for (int from = 0; from < n; ++from) {
    if (from != previous) {
      EXPECT_TRUE(in[from].empty()) << "from " << from;
      continue;
    }
    ASSERT_EQ(in[from].size(), incoming[from]);
    for (int k = 0; k < from + 3; ++k) EXPECT_EQ(in[from][k], std::byte(from * 16 + k));
  }
}

TEST(Ranks, EveryRankCutsTheBoxAlike) {
  const Communicator& w = world();
  Bricks b(w.size(), Vec3(0, 0, 0), Vec3(0.64, 0.64, 1.1));
  std::vector<Vec3> p;
  for (int k = 0; k < 500; ++k) p.emplace_back(0.001 * k, 0.3, 0.002 * k);
  b.balance(p, 0.05);
  std::vector<std::byte> cuts;
  for (int a = 0; a < 3; ++a) {
    for (double c : b.cuts(a)) {
      const auto* bytes = reinterpret_cast<const std::byte*>(&c);
      cuts.insert(cuts.end(), bytes, bytes + sizeof c);
    }
  }
  EXPECT_EQ(w.broadcast(cuts), cuts);
  EXPECT_EQ(b.ranks(), w.size());
}
