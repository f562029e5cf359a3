/// The silo study (granular/silo_study.hpp) on a small silo: its slices' vertical stresses and
/// its wall's shear satisfy the static bed's virial identity; its discharges lose mass only
/// through the orifice, monotonically; a scene without the study's walls is refused by name.
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

SiloStudyResult smallStudy() {
  static const SiloStudyResult result = [] {
    SiloStudyOptions options;
    options.dischargeTime = 0.5;
    return runSiloStudy(loadScene(kSilo), options);
  }();
  return result;
}

}  // namespace

// A bed at rest, each particle in equilibrium: Σ_c F_z l_z over every contact (pairs cancel at
// their common point) is Σ_wall F_z z_c − g Σ m_i z_i, the floor's contacts lying at z = 0.
// In the study's terms, with each mass and wall contact at its level's middle z_k:
//   Σ_k σ_v,k V_k = g Σ_k ρ_k V_k z_k − Σ_k τ_w,k A_k z_k.
// The levels' sums agree to a few per cent (the particles are spread over each level).
TEST(SiloStudy, TheSlicesStressesAndTheWallsShearSatisfyTheStaticVirial) {
  const SiloStudyResult r = smallStudy();
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
