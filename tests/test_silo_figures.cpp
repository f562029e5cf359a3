/// The silo study's figures drawn from a result made by hand from the closed forms (Janssen's
/// σ_v with λ = 0.13, Beverloo's rates with C = 0.58 and k = 1.5), against golden images: the
/// vertical stress with its fitted curve and the hydrostatic line, and the discharged mass with
/// Beverloo's lines. The measured points lie on the curves by construction.
#include <gtest/gtest.h>

#include <algorithm>

#include "golden.hpp"
#include "granular/beverloo.hpp"
#include "granular/discharge_rate.hpp"
#include "granular/janssen.hpp"
#include "silo_figures.hpp"

using namespace granular;

namespace {

SiloStudyResult handMadeSilo() {
  SiloStudyResult r;
  r.radius = 0.17;
  r.particleDiameter = 0.017;
  r.surface = 0.45;
  r.bulkDensity = 320.0;
  r.bedMass = 13.0;
  const double gamma = r.bulkDensity * r.gravity;
  const double rh = circleHydraulicRadius(2.0 * r.radius);
  std::vector<double> depths, stresses;
  for (int k = 0; k < 14; ++k) {
    SiloLevel l;
    l.zLow = 0.034 * k;
    l.zHigh = l.zLow + 0.034;
    l.depth = std::max(0.0, r.surface - 0.5 * (l.zLow + l.zHigh));
    l.verticalStress = janssenVerticalStress(l.depth, gamma, rh, 0.13);
    l.wallPressure = 0.6 * l.verticalStress;
    l.wallPressureStd = 3.0;
    l.wallShear = 0.13 * l.verticalStress;
    l.bulkDensity = r.bulkDensity;
    l.inBed = l.zHigh <= r.surface && k > 0;
    if (l.inBed) {
      depths.push_back(l.depth);
      stresses.push_back(l.verticalStress);
    }
    r.levels.push_back(l);
  }
  r.janssen = fitJanssen(depths, stresses, rh, gamma);
  std::vector<double> orifices, rates;
  for (double orifice : {0.119, 0.153}) {
    SiloDischarge d;
    d.orifice = orifice;
    const double w = beverlooRate(0.58, 1.5, r.bulkDensity, r.gravity, orifice, 0.017);
    for (int k = 0; k <= 100; ++k) {
      const double t = 0.01 * k;
      d.time.push_back(t);
      d.discharged.push_back(std::max(0.0, w * (t - 0.05)));
    }
    d.steady = steadyDischargeRate(d.time, d.discharged);
    d.flowed = true;
    for (const SiloLevel& l : r.levels) d.wallPressure.push_back(0.95 * l.wallPressure);
    orifices.push_back(orifice);
    rates.push_back(d.steady.rate);
    r.discharges.push_back(d);
  }
  r.beverloo = fitBeverloo(orifices, rates, r.bulkDensity, r.gravity, 0.017);
  r.beverlooFitted = true;
  return r;
}

}  // namespace

TEST(SiloFigures, VerticalStressWithJanssensCurveMatchesItsGolden) {
  const SiloStudyResult r = handMadeSilo();
  ASSERT_NEAR(r.janssen.lambda, 0.13, 1e-6);  // the points lie on the curve
  EXPECT_TRUE(
      granular::testing::matchesGolden(app::verticalStressFigure(r), "silo_vertical_stress"));
}

TEST(SiloFigures, DischargeWithBeverloosLinesMatchesItsGolden) {
  const SiloStudyResult r = handMadeSilo();
  ASSERT_NEAR(r.beverloo.c, 0.58, 1e-6);
  EXPECT_TRUE(granular::testing::matchesGolden(app::dischargeFigure(r), "silo_discharge"));
}
