/// The silo study (granular/silo_study.hpp) on a small silo: its slices' vertical stresses and
/// its wall's shear satisfy the static bed's virial identity and each level's vertical balance;
/// its discharges lose mass only through the orifice, monotonically; a scene without the
/// study's walls is refused by name. On a small silo with a hopper: the cylinder's levels start
/// at the transition and balance there too, the hopper's wall is measured in bands, its
/// shortened cone discharges faster, and a hopper that does not fit is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "granular/error.hpp"
#include "granular/silo_study.hpp"

using namespace granular;

namespace {

const std::filesystem::path kSilo =
    std::filesystem::path(GRANULAR_SOURCE_DIR) / "tests/scenes/silo-study-small.toml";

const std::filesystem::path kHopper =
    std::filesystem::path(GRANULAR_SOURCE_DIR) / "tests/scenes/silo-hopper-small.toml";

SiloStudyResult smallStudy() {
  static const SiloStudyResult result = [] {
    SiloStudyOptions options;
    options.dischargeTime = 0.5;
    return runSiloStudy(loadScene(kSilo), options);
  }();
  return result;
}

SiloStudyResult hopperStudy() {
  static const SiloStudyResult result = [] {
    SiloStudyOptions options;
    options.dischargeTime = 0.5;
    return runSiloStudy(loadScene(kHopper), options);
  }();
  return result;
}

/// A static bed's vertical balance across the middle of each level in the bed: the weight
/// above it less what the wall's shear carries above it crosses the section there as the
/// level's σ_v (its slice mean; the force across a plane is linear in the height within the
/// level to the particles' scale). Returns the largest miss as a fraction of the weight above.
double worstVerticalBalance(const SiloStudyResult& r) {
  const double section = std::numbers::pi * r.radius * r.radius;
  const double perimeter = 2.0 * std::numbers::pi * r.radius;
  double worst = 0.0;
  for (std::size_t j = 0; j < r.levels.size(); ++j) {
    if (!r.levels[j].inBed) continue;
    double weight = 0.0, carried = 0.0;
    for (std::size_t k = j; k < r.levels.size(); ++k) {
      const SiloLevel& l = r.levels[k];
      const double share = k == j ? 0.5 : 1.0;
      const double dz = l.zHigh - l.zLow;
      weight += share * r.gravity * l.bulkDensity * section * dz;
      carried += share * l.wallShear * perimeter * dz;
    }
    const double crossing = r.levels[j].verticalStress * section;
    worst = std::max(worst, std::abs(crossing - (weight - carried)) / weight);
  }
  return worst;
}

}  // namespace

// (Each test runs in a process of its own: one study a test, its checks together.)
TEST(SiloStudy, AHopperSilosCylinderStartsAtTheTransitionBalancesThereAndItsHopperIsInBands) {
  const SiloStudyResult r = hopperStudy();
  // Each level in the bed balances, as on a flat floor (below).
  EXPECT_LT(worstVerticalBalance(r), 0.08);
  ASSERT_TRUE(r.hasHopper);
  EXPECT_NEAR(r.transition, 0.0086603 + 0.0606218, 1e-12);
  EXPECT_NEAR(r.hopperHalfAngle * 180.0 / std::numbers::pi, 30.0, 1e-3);
  ASSERT_FALSE(r.levels.empty());
  EXPECT_DOUBLE_EQ(r.levels.front().zLow, r.transition);
  ASSERT_GE(r.hopperBands.size(), 2u);
  EXPECT_DOUBLE_EQ(r.hopperBands.front().zLow, 0.0086603);
  EXPECT_DOUBLE_EQ(r.hopperBands.back().zHigh, r.transition);
  for (std::size_t k = 0; k < r.hopperBands.size(); ++k) {
    EXPECT_GT(r.hopperBands[k].wallPressure, 0.0) << "band " << k;
    if (k > 0) {
      EXPECT_DOUBLE_EQ(r.hopperBands[k].zLow, r.hopperBands[k - 1].zHigh);
    }
  }
  // The bed's surface counts the cylinder's part of the mass only: above the transition.
  EXPECT_GT(r.surface, r.transition + 4.0 * r.particleDiameter);
  ASSERT_EQ(r.discharges.size(), 2u);
  for (const SiloDischarge& d : r.discharges) {
    EXPECT_EQ(d.hopperPressure.size(), r.hopperBands.size());
  }
  // Without its lowest piece the cone ends in the wider outlet, and lets out more.
  EXPECT_DOUBLE_EQ(r.discharges[1].orifice, 0.05);
  EXPECT_GT(r.discharges[1].discharged.back(), r.discharges[0].discharged.back());
}

TEST(SiloStudy, AHopperNarrowerThanTheWidestOrificeIsRefused) {
  Scene scene = loadScene(kHopper);
  for (Wall& w : scene.walls) {
    if (w.name == "hopper") w.radiusStart = 0.02;  // the ring's outlet is 0.025 m across
  }
  try {
    runSiloStudy(scene, {});
    FAIL() << "no refusal";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'hopper'"), std::string::npos) << e.what();
  }
}

// A bed at rest, each particle in equilibrium: Σ_c F_z l_z over every contact (pairs cancel at
// their common point) is Σ_wall F_z z_c − g Σ m_i z_i, the floor's contacts lying at z = 0.
// In the study's terms, with each mass and wall contact at its level's middle z_k:
//   Σ_k σ_v,k V_k = g Σ_k ρ_k V_k z_k − Σ_k τ_w,k A_k z_k.
// The levels' sums agree to a few per cent (the particles are spread over each level).
// And each level in the bed balances: the wall carries a share that a sign error in its shear,
// or σ_v over the wrong area, would break by tens of per cent.
TEST(SiloStudy, TheSlicesStressesAndTheWallsShearSatisfyTheStaticVirialAndEachLevelBalances) {
  const SiloStudyResult r = smallStudy();
  EXPECT_LT(worstVerticalBalance(r), 0.08);
  ASSERT_GE(r.levels.size(), 4u);
  const double section = std::numbers::pi * r.radius * r.radius;
  double virial = 0.0, weightMoment = 0.0, wallMoment = 0.0;
  for (const SiloLevel& l : r.levels) {
    const double dz = l.zHigh - l.zLow, z = 0.5 * (l.zLow + l.zHigh);
    virial += l.verticalStress * section * dz;
    weightMoment += r.gravity * l.bulkDensity * section * dz * z;
    wallMoment += l.wallShear * 2.0 * std::numbers::pi * r.radius * dz * z;
  }
  EXPECT_GT(virial, 0.0);
  // The lifted wall carries a share of the weight that a sign error in its shear would show:
  // the identity then misses by twice the wall's moment.
  EXPECT_GT(wallMoment, 0.15 * weightMoment);
  EXPECT_NEAR(virial, weightMoment - wallMoment, 0.05 * weightMoment);
  // The bed's mass as the levels hold it.
  double mass = 0.0;
  for (const SiloLevel& l : r.levels) mass += l.bulkDensity * section * (l.zHigh - l.zLow);
  EXPECT_NEAR(mass, r.bedMass, 1e-9 * r.bedMass);
}

TEST(SiloStudy, EachOrificeDischargesMonotonicallyAndNoMoreThanTheBed) {
  const SiloStudyResult r = smallStudy();
  ASSERT_EQ(r.discharges.size(), 2u);
  EXPECT_DOUBLE_EQ(r.discharges[0].orifice, 0.04);
  EXPECT_DOUBLE_EQ(r.discharges[1].orifice, 0.05);
  for (const SiloDischarge& d : r.discharges) {
    ASSERT_FALSE(d.discharged.empty());
    for (std::size_t k = 1; k < d.discharged.size(); ++k) {
      EXPECT_GE(d.discharged[k], d.discharged[k - 1]);
    }
    EXPECT_LE(d.discharged.back(), r.bedMass);
  }
  // The wider orifice lets out more in the same time.
  EXPECT_GT(r.discharges[1].discharged.back(), r.discharges[0].discharged.back());
}

TEST(SiloStudy, ASceneWithoutTheStudysWallsIsRefusedNamingThem) {
  Scene scene = loadScene(kSilo);
  for (Wall& w : scene.walls) {
    if (w.name == "gate") w.name = "door";
  }
  try {
    runSiloStudy(scene, {});
    FAIL() << "no refusal";
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'gate'"), std::string::npos) << e.what();
  }
}
