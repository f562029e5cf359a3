#pragma once
/// The silo study of `granular silo`: a cylindrical silo with a flat floor is filled by pouring
/// (the scene's first stage), its wall pressures and vertical stresses are measured at rest, and
/// it is discharged through each of its orifices in turn from the same settled bed.
///
/// The scene names its walls: "wall", the cylinder (axis +z, base on the floor); "gate", the disc
/// closing the smallest orifice; "ring1" … "ringN", annuli each widening the orifice to its outer
/// radius; "floor", the annulus out to the cylinder. Orifice k (1-based) opens by taking away the
/// gate and rings 1 … k − 1, so the orifices are the gate's diameter and the rings' outer
/// diameters.
///
/// A silo with a conical hopper adds "hopper", a cone (axis +z) from the floor's height or above,
/// where its radius is the largest orifice's or more, widening to the cylinder's radius at the
/// transition; the cylinder then starts at the transition or below it. Its rings may be pieces
/// of the hopper's cone below it (taking them away shortens the hopper to a wider outlet), the
/// gate closing the lowest. The cylinder's levels start at the transition, and the hopper's
/// wall is measured in bands of its own.
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "granular/beverloo.hpp"
#include "granular/discharge_rate.hpp"
#include "granular/janssen.hpp"
#include "granular/scene.hpp"
#include "granular/slice_stress.hpp"
#include "granular/wall_bands.hpp"

namespace granular {

struct SiloStudyResult;

/// How the study measures.
struct SiloStudyOptions {
  double restWindow = 0.2;       ///< time the settled bed is sampled over [s]
  double sampleInterval = 0.01;  ///< between samples, at rest and during discharge [s]
  double bandHeight = 0.0;       ///< bands and slices [m]; 0: two mean particle diameters
  double dischargeTime = 1.0;    ///< each discharge's length [s]
  /// After the fill, the cylinder is lifted by this many mean particle diameters, slowly, so
  /// that the bed slides down along the whole wall and the wall's friction is mobilised at
  /// every height (a poured bed's top carries almost none, which Janssen's law assumes it
  /// does); 0 measures the bed as poured [-].
  double wallLift = 0.25;
  double wallLiftSpeed = 0.02;  ///< the cylinder's speed while lifted [m/s]
  /// Called every few hundred steps with what runs ("fill", "rest", "orifice 2 of 4").
  std::function<void(const Simulation&, const std::string& phase)> onProgress;
  /// Called once with the settled bed at the end of the rest window, before the discharges,
  /// and the result so far (the geometry, the levels and the fits at rest): for figures of it.
  std::function<void(const Simulation& settled, const SiloStudyResult& atRest)> onSettled;
};

/// One height of the bed at rest: the wall's band and the section's slice at the same heights.
struct SiloLevel {
  double zLow = 0, zHigh = 0;    ///< [m]
  double depth = 0;              ///< of the level's middle below the bed's surface [m]
  double wallPressure = 0;       ///< p_h, the mean over the samples [Pa]
  double wallPressureStd = 0;    ///< its scatter over the samples [Pa]
  double wallShear = 0;          ///< upward shear of the wall on the bed, τ_w [Pa]
  double verticalStress = 0;     ///< σ_v of Eq. (1) over the slice, the mean [Pa]
  double bulkDensity = 0;        ///< the slice's mass over its volume, the mean [kg/m³]
  double lateralRatio = 0;       ///< K = p_h / σ_v [-]
  double mobilisedFriction = 0;  ///< τ_w / p_h [-]
  bool inBed = false;            ///< a band or more below the surface and above the floor
};

/// One band of a conical hopper's wall: its normal pressure at rest.
struct HopperBand {
  double zLow = 0, zHigh = 0;  ///< [m]
  double wallPressure = 0;     ///< p_n, normal to the hopper's wall, the mean [Pa]
  double wallPressureStd = 0;  ///< its scatter over the samples [Pa]
};

/// One orifice's discharge.
struct SiloDischarge {
  double orifice = 0;              ///< D₀ [m]
  std::vector<double> time;        ///< since the orifice opened [s]
  std::vector<double> discharged;  ///< mass discharged by then [kg]
  SteadyRate steady;               ///< the steady rate, 20-80 % of what it discharged
  /// p_h per level during the steady window (the switch from the filling pressures) [Pa].
  std::vector<double> wallPressure;
  /// The hopper's p_n per band during the steady window, as wallPressure; empty without a
  /// hopper [Pa].
  std::vector<double> hopperPressure;
  /// The flowing material's effective angle of internal friction [rad]: sin φ = (σ1 − σ3) /
  /// (σ1 + σ3) of Eq. (1) in a representative sphere on the axis in the converging flow above
  /// the orifice (centred D₀ above it, of radius D₀/3), the mean over the steady window; NaN
  /// when it did not flow.
  double internalFriction = 0;
  /// The bulk density in the same sphere over the same window, NaN when it did not flow: the
  /// flowing material's, looser than the bed's at rest [kg/m³].
  double flowDensity = 0;
  /// A steady rate was measured: ten samples or more in its window, and the flow over the
  /// last quarter of the discharge at half that rate or more (else it arched and stopped).
  bool flowed = false;
};

struct SiloStudyResult {
  double gravity = 9.81;          ///< |g| [m/s²]
  double radius = 0;              ///< the cylinder's [m]
  double floor = 0;               ///< the gate's height, the lowest outlet's [m]
  double particleDiameter = 0;    ///< the mean of the particles' [m]
  double surface = 0;             ///< the bed's surface: its height at its mean bulk density [m]
  double bedMass = 0;             ///< [kg]
  double bulkDensity = 0;         ///< mean over the levels in the bed [kg/m³]
  double fillSeconds = 0;         ///< wall-clock time of the fill [s]
  double wallLift = 0;            ///< how far the cylinder was lifted after the fill [m]
  std::vector<SiloLevel> levels;  ///< the cylinder's, from the floor or the transition up
  /// The conical hopper, when the silo has one: its half-angle from the vertical [rad], the
  /// transition's height [m], its wall's bands (from the floor up); transition = the floor's
  /// height and no bands without one.
  bool hasHopper = false;
  double hopperHalfAngle = 0;
  double transition = 0;
  std::vector<HopperBand> hopperBands;
  std::size_t restSamples = 0;
  JanssenFit janssen;      ///< λ fitted to σ_v over the levels in the bed, γ = ρ_b g
  JanssenFit janssenBoth;  ///< λ and γ both fitted
  /// λ measured from the wall's forces: Σ τ_w / Σ σ_v over the levels in the bed, Janssen's
  /// balance τ_w = μ_mob K σ_v summed over the depth (a mean of the levels' ratios would weigh
  /// the unloaded top as much as the deep bed) [-].
  double lambdaMeasured = 0;
  double lateralRatio = 0;       ///< K, the mean over the levels in the bed [-]
  double mobilisedFriction = 0;  ///< μ_mob, the mean over the levels in the bed [-]
  std::vector<SiloDischarge> discharges;
  /// The mean of the discharges' internalFriction where measured, NaN if nowhere [rad].
  double internalFriction = 0;
  BeverlooFit beverloo;  ///< over the orifices that flowed
  bool beverlooFitted = false;
};

/// Runs the study on the scene (its first stage fills the silo). Throws ConfigError naming a
/// wall the scene lacks or has of the wrong shape.
SiloStudyResult runSiloStudy(const Scene& scene, const SiloStudyOptions& options);

}  // namespace granular
