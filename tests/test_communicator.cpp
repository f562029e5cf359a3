/// The one-process communicator (granular/communicator.hpp); tests/ranks/ runs the same
/// contract on 1 to 4 MPI ranks.
#include <gtest/gtest.h>

#include "granular/communicator.hpp"

using namespace granular;

TEST(Communicator, OneProcessIsRankZeroOfOneAndReturnsItsArguments) {
  const std::unique_ptr<Communicator> c = singleProcess();
  EXPECT_EQ(c->rank(), 0);
  EXPECT_EQ(c->size(), 1);
  EXPECT_EQ(c->maxOverRanks(-2.5), -2.5);
  EXPECT_TRUE(c->anyOverRanks(true));
  EXPECT_FALSE(c->anyOverRanks(false));
  EXPECT_EQ(c->sumOverRanks(42), 42u);
  std::vector<ExactSum> sums(2);
  sums[0].add(0.1);
  sums[1].add(-3.0);
  c->mergeOverRanks(sums);
  EXPECT_EQ(sums[0].value(), 0.1);
  EXPECT_EQ(sums[1].value(), -3.0);
  const std::vector<std::vector<std::byte>> out{{std::byte{1}, std::byte{2}}};
  EXPECT_EQ(c->exchange(out), out);
  EXPECT_EQ(c->exchangeKnown(out, {2}), out);
  std::vector<std::uint64_t> counts{3, 4};
  c->mergeOverRanks(sums, counts);
  EXPECT_EQ(sums[0].value(), 0.1);
  EXPECT_EQ(counts, (std::vector<std::uint64_t>{3, 4}));
  EXPECT_EQ(c->broadcast(out[0]), out[0]);
}

TEST(Communicator, CarriedWordsSummedElementByElementAreTheMerge) {
  // What an MPI reduction of the words does (ExactSum::words): three accumulators' words summed
  // as integers, flags ORed, give their merge to the bit.
  ExactSum parts[3], merged;
  double x = 1.0;
  for (int k = 0; k < 3000; ++k) {
    x = x * 1.37 + 0.001;
    if (x > 1e30) x = 1e-20 * x;
    const double term = (k % 3 == 1 ? -x : x) * (k % 7 == 0 ? 1e-15 : 1.0);
    parts[k % 3].add(term);
    merged.add(term);
  }
  ExactSum::Words sum{};
  for (const ExactSum& p : parts) {
    const ExactSum::Words w = p.words();
    for (int i = 0; i < ExactSum::kLimbs + 1; ++i) sum[i] += w[i];
    sum[ExactSum::kLimbs + 1] |= w[ExactSum::kLimbs + 1];
  }
  EXPECT_EQ(ExactSum::fromWords(sum).value(), merged.value());
  EXPECT_NE(merged.value(), 0.0);
}
