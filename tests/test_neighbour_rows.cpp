/// The neighbour list's compact layout (core/engine/src/simulation_state.hpp): pairs stored as
/// compressed rows (rowStart) walked by RowWalker in runs of pairs, and reference positions kept
/// in single precision with a bound on their rounding that the staleness test adds.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "simulation_state.hpp"

namespace granular {
namespace {

/// Rows for `lengths[i]` pairs of particle i, and the first particle of every pair as the plain
/// expansion gives it.
struct Rows {
  std::vector<std::uint32_t> rowStart{0}, first;
};
Rows rowsOf(const std::vector<std::uint32_t>& lengths) {
  Rows r;
  for (std::size_t i = 0; i < lengths.size(); ++i) {
    r.rowStart.push_back(r.rowStart.back() + lengths[i]);
    r.first.insert(r.first.end(), lengths[i], static_cast<std::uint32_t>(i));
  }
  return r;
}

/// Every pair's first particle as RowWalker gives it, from particle `from` on, in runs of
/// `run` pairs.
std::vector<std::uint32_t> walked(const Rows& r, std::size_t from, std::size_t run) {
  std::vector<std::uint32_t> out;
  RowWalker walker(r.rowStart, from);
  const std::size_t end = r.rowStart.back();
  std::uint32_t starts[RowWalker::kMaxRun];
  for (std::size_t begin = r.rowStart[from]; begin < end; begin += run) {
    const std::size_t count = std::min(run, end - begin);
    std::uint32_t i = walker.mark(begin, count, starts);
    for (std::size_t e = 0; e < count; ++e) out.push_back(i += starts[e]);
    walker.reached(i);
  }
  return out;
}

TEST(NeighbourRows, TheWalkerGivesEveryPairItsFirstParticle) {
  // Rows of 0 to 9 pairs, many empty ones among them (also runs of empty rows at the start, at
  // the end and across a run's boundary), walked in runs of several lengths, from the first
  // particle and from a later one as a particle block starts.
  std::mt19937 random(7);
  std::vector<std::uint32_t> lengths = {0, 0, 3};
  for (int i = 0; i < 2000; ++i) {
    const std::uint32_t roll = random() % 14;
    lengths.push_back(roll < 5 ? 0 : roll - 5);
  }
  lengths.insert(lengths.end(), {0, 0, 0});
  const Rows r = rowsOf(lengths);
  for (std::size_t run : {1u, 7u, 64u}) {
    EXPECT_EQ(walked(r, 0, run), r.first) << "runs of " << run;
    const std::size_t from = 1000;
    const std::vector<std::uint32_t> tail(r.first.begin() + r.rowStart[from], r.first.end());
    EXPECT_EQ(walked(r, from, run), tail) << "runs of " << run << " from particle " << from;
  }
}

TEST(NeighbourRows, RowsAndFirstParticlesConvertBothWaysAndDisorderIsRefused) {
  // The checkpoint stores the first particle of each pair; memory holds rows.
  const Rows r = rowsOf({2, 0, 0, 3, 1, 0});
  NeighbourList list;
  list.second.assign(r.first.size(), 5);
  ASSERT_TRUE(rowsFromFirst(list, r.first, 6));
  EXPECT_EQ(list.rowStart, r.rowStart);
  EXPECT_EQ(firstOfPairs(list), r.first);
  std::vector<std::uint32_t> unsorted = r.first;
  std::swap(unsorted[1], unsorted[3]);
  EXPECT_FALSE(rowsFromFirst(list, unsorted, 6));
  EXPECT_FALSE(rowsFromFirst(list, r.first, 4)) << "a first particle out of range";
}

TEST(NeighbourRows, RoundedReferencePositionsNeverHideTwoMovesThatCloseTheSkin) {
  // Far from the origin a float is coarse: at 1000 m its spacing is 61 µm. Two particles that
  // have moved by half the skin each (after which they may have closed the skin between them)
  // must make the list stale even when the rounding of a reference position points the same
  // way as the move and so shortens the move measured from it.
  const double skin = 1e-4;           // [m]
  const double x0 = 1000.0 + 3.0e-5;  // rounds down to 1000 m: the reference is 30 µm short
  NeighbourList list;
  list.skin = skin;
  list.valid = true;
  Particles p;
  p.position = {Vec3(x0, 0, 0), Vec3(x0 + 1.0, 0, 0)};
  setReferencePositions(list, p.position);
  ASSERT_EQ(static_cast<double>(list.referencePosition[0].x()), 1000.0);
  ASSERT_GT(list.referenceRounding, 3.0e-5);
  p.position[0].x() -= 0.5 * skin;  // towards the rounded reference: measured as 20 µm only
  p.position[1].x() -= 0.5 * skin;
  const LargestMoves measured = largestMoves(list, p, 0, p.size());
  ASSERT_LT(std::sqrt(measured.second), 0.5 * skin)
      << "the test needs a move the rounding shortens";
  EXPECT_TRUE(neighbourListStale(list, p, {}, measured));
  // Near the origin the bound is tiny: the list stays fresh for moves well inside the skin,
  // and for one particle's move of nearly the skin while the other stays.
  p.position = {Vec3(0.25, 0.5, 0.75), Vec3(1.0, 0.5, 0.75)};
  setReferencePositions(list, p.position);
  EXPECT_LT(list.referenceRounding, 2e-7);  // 2⁻²⁴ √3 m
  p.position[0].x() += 0.4 * skin;
  EXPECT_FALSE(neighbourListStale(list, p, {}, largestMoves(list, p, 0, p.size())));
  p.position[0].x() += 0.5 * skin;
  EXPECT_FALSE(neighbourListStale(list, p, {}, largestMoves(list, p, 0, p.size())));
  p.position[1].x() -= 0.1 * skin;  // now they may have closed the skin
  EXPECT_TRUE(neighbourListStale(list, p, {}, largestMoves(list, p, 0, p.size())));
}

/// The pairs j > i of each particle within R_i + R_j + margin, by testing every pair.
std::vector<std::vector<std::uint32_t>> pairsWithin(const Particles& p, double margin) {
  std::vector<std::vector<std::uint32_t>> rows(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    for (std::size_t j = i + 1; j < p.size(); ++j) {
      const double reach = p.radius[i] + p.radius[j] + margin;
      if ((p.position[j] - p.position[i]).squaredNorm() < reach * reach) {
        rows[i].push_back(static_cast<std::uint32_t>(j));
      }
    }
  }
  return rows;
}

}  // namespace

// The cell search, on any thread count, lists exactly the pairs within reach, those placed a
// rounding's width inside and outside it included.
TEST(NeighbourRows, TheSearchListsExactlyThePairsWithinReachOnAnyThreadCount) {
  std::mt19937_64 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Particles p;
  for (int k = 0; k < 2000; ++k) {
    const Vec3 x(0.2 * unit(random), 0.2 * unit(random), 0.2 * unit(random));
    p.add(x, 0.004 + 0.006 * unit(random), 2500.0);
  }
  const double skin = 0.003;
  // Pairs at the reach to the last bit: one just inside, one just outside.
  for (int k = 0; k < 40; ++k) {
    const Vec3 x(0.2 * unit(random), 0.2 * unit(random), 0.2 * unit(random));
    const double ri = 0.005, rj = 0.007, reach = ri + rj + skin;
    const double gap = k % 2 == 0 ? std::nextafter(reach, 0.0) : reach;
    p.add(x, ri, 2500.0);
    p.add(x + Vec3(gap, 0.0, 0.0), rj, 2500.0);
  }
  const std::vector<std::vector<std::uint32_t>> expected = pairsWithin(p, skin);
  std::size_t pairs = 0;
  for (const auto& row : expected) pairs += row.size();
  ASSERT_GT(pairs, 1000u);
  for (int threads : {1, 2, 3}) {
    NeighbourList list;
    list.skin = skin;
    rebuildNeighbourList(list, p, {}, false, 0.0, threads);
    ASSERT_EQ(list.rowStart.size(), p.size() + 1);
    for (std::size_t i = 0; i < p.size(); ++i) {
      const std::vector<std::uint32_t> row(list.second.begin() + list.rowStart[i],
                                           list.second.begin() + list.rowStart[i + 1]);
      ASSERT_EQ(row, expected[i]) << "particle " << i << ", " << threads << " threads";
    }
  }
}

}  // namespace granular
