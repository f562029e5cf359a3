/// The time-step checks and the warnings of deep overlaps made at load
/// (step_checks_at_load.hpp).
#include "step_checks_at_load.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <string_view>
#include <variant>

#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/network_step.hpp"

namespace granular {

double defaultImpactSpeed(const MotionBound& bound, const BoxSpec& box, const Vec3& gravity,
                          const std::vector<StageSpec>& stages, const std::vector<Wall>& walls) {
  const double height = std::max(0.0, bound.highestTop - box.min.z());
  double wall = 0.0;
  // A wall's fastest surface point: its translation, plus its turn times the farthest point
  // of its shape from the pivot.
  for (const Wall& w : walls) {
    const double reach = (w.point - w.pivot).norm() + w.halfSide[0] + w.halfSide[1] + w.length +
                         std::max(w.radiusStart, w.radiusEnd);
    wall = std::max(wall, w.velocity.norm() + w.angularVelocity.norm() * reach);
  }
  for (const StageSpec& stage : stages) {
    for (const WallMotion& motion : stage.wallMotions)
      wall = std::max(wall, motion.velocity.norm());
  }
  const double particle = bound.fastest + std::sqrt(2.0 * gravity.norm() * height) + 2.0 * wall;
  return particle > 0.0 ? 2.0 * particle : 1.0;
}

namespace {

/// A reader of `key`'s table, or of the root when the table is absent (a default is at fault).
TomlTableReader tableOrRoot(const TomlTableReader& root, std::string_view key,
                            const std::string& file) {
  if (const toml::table* table = root.subTable(key)) {
    return TomlTableReader(*table, std::string(key), file);
  }
  return root;
}

/// x to 4 significant digits, "%.4g", rounded down when `down` (a limit a user may copy).
std::string fourDigits(double x, bool down = false) {
  if (down && x > 0.0) {
    const double unit = std::pow(10.0, std::floor(std::log10(x)) - 3.0);
    x = std::floor(x / unit) * unit;
  }
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", x);
  return buffer;
}

/// Why a fixed step is above the one the network of a dense bed allows (denseBedStep).
std::string denseBedRefusal(const SimulationConfig& config, const NetworkStep& bed, double radius) {
  const bool gear = config.integrator == Integrator::Gear5;
  return "time step " + formatNumber(config.timeStep) +
         " s is above the step the contact network of a dense bed allows with rolling "
         "resistance, " +
         fourDigits(bed.dt) + " s: " + (gear ? "gear5" : "velocity Verlet") +
         " is stable for ω Δt <= " + fourDigits(bed.dt * bed.omegaMax) +
         " at the network's damping ratio " + fourDigits(bed.zeta) +
         " (the rolling dashpots turn the spheres' own rotation), and its highest frequency is "
         "at most " +
         fourDigits(bed.omegaMax) + " rad/s (a face-centred cubic block of spheres of radius " +
         fourDigits(radius) + " m, 12 contacts each, on the floor); use at most " +
         fourDigits(bed.dt, true) + " s, or time_step = \"auto\"";
}

/// Where a warning about `key` of `table` points: the key's line, or the table's, or the file.
std::string warningPrefix(const TomlTableReader& root, const std::string& file,
                          std::string_view table, std::string_view key) {
  if (const toml::table* t = root.subTable(table)) {
    const TomlTableReader r(*t, std::string(table), file);
    if (r.has(key)) return r.messagePrefix(key);
  }
  return file + ": ";
}

}  // namespace

void checkTimeStep(const TomlTableReader& root, const std::string& file, Scene& scene,
                   const MotionBound& bound) {
  Material material = scene.simulation.material;
  if (scene.totalMass) {
    material.density = *scene.totalMass / bound.volume;
    const double maxDensity = findParameter("density")->range.hi;  // the declared bound
    if (!(material.density <= maxDensity)) {
      root.fail("total_mass", "gives the particles a density of " + formatNumber(material.density) +
                                  " kg/m³; must be at most " + formatNumber(maxDensity));
    }
  }
  ContactScale scale;
  try {
    scale = stiffestContact(material, bound.smallestRadius, scene.simulation.impactSpeed);
  } catch (const ConfigError& e) {
    tableOrRoot(root, "material", file).fail("normal_damping", e.what());
  }
  if (scene.simulation.step.automatic) {
    // The largest step the engine may choose: the accuracy floor.
    scene.simulation.timeStep = scale.duration / scene.simulation.step.contactResolution;
    return;
  }
  const TomlTableReader simulation(*root.subTable("simulation"), "simulation", file);
  if (RollingResistance::active(material)) {
    // The rolling dashpots act on the spheres' own rotation, whose inertia is small: their rates
    // shrink Gear's interval, which the binary contact's duration does not see. The step is
    // judged on the network of a dense bed of the smallest spheres instead.
    SimulationConfig config = scene.simulation;
    config.material = material;
    const NetworkStep bed = denseBedStep(config, bound.smallestRadius);
    if (!(scene.simulation.timeStep <= bed.dt)) {
      simulation.fail("time_step", denseBedRefusal(scene.simulation, bed, bound.smallestRadius));
    }
  }
  for (const Generator& g : scene.generators) {
    if (std::holds_alternative<CsvGenerator>(g)) return;  // the engine checks the network
  }
  try {
    requireStableStep(scene.simulation.timeStep, scale, scene.simulation.integrator);
  } catch (const ConfigError& e) {
    if (scene.totalMass) {
      // The density, hence the contact duration, comes from total_mass: name both keys.
      root.fail("total_mass", "gives the particles a density of " + formatNumber(material.density) +
                                  " kg/m³, so " + e.what() +
                                  "; raise total_mass or lower simulation.time_step");
    }
    simulation.fail("time_step", e.what());
  }
  try {
    requireStableTangentialDamping(material, scene.simulation.timeStep,
                                   scene.simulation.integrator);
  } catch (const ConfigError& e) {
    tableOrRoot(root, "material", file).fail("tangential_damping", e.what());
  }
}

void warnOfDeepOverlaps(const TomlTableReader& root, const std::string& file, Scene& scene,
                        const MotionBound& bound, bool impactSpeedGiven) {
  Material material = scene.simulation.material;
  if (scene.totalMass) material.density = *scene.totalMass / bound.volume;
  const double r = bound.smallestRadius;
  const double m = material.density * 4.0 / 3.0 * std::numbers::pi * r * r * r;
  // A declared approach speed as it is; the default's bound (two spheres head-on, each at the
  // largest speed a particle reaches) far exceeds what a bed's impacts meet, so a particle at
  // that largest speed striking a wall or a sphere at rest stands for it.
  const double u =
      impactSpeedGiven ? scene.simulation.impactSpeed : 0.5 * scene.simulation.impactSpeed;
  try {
    // A wall contact and a pair of the smallest spheres (a pair's overlap beyond a radius puts
    // each centre inside the other sphere).
    const double wall = peakImpactOverlap(material, r, m, u);
    const double pair = peakImpactOverlap(material, 0.5 * r, 0.5 * m, u);
    if (std::max(wall, pair) > r) {
      const double held = std::min(speedForPeakOverlap(material, r, m, r),
                                   speedForPeakOverlap(material, 0.5 * r, 0.5 * m, r));
      const std::string where =
          impactSpeedGiven
              ? warningPrefix(root, file, "simulation", "impact_speed")
              : file + ": the particles' initial speeds, fall height and wall speeds let a " +
                    "particle strike at up to " + fourDigits(u) + " m/s: ";
      scene.warnings.push_back(
          where + "an impact at " + fourDigits(u) + " m/s overlaps spheres of radius " +
          fourDigits(r) + " m by " + fourDigits(std::max(wall, pair) / r) +
          " radii (the peak overlap of a head-on impact under the normal law): beyond a radius "
          "spheres pass through each other and through walls, whatever the time step; this "
          "material holds impacts up to " +
          fourDigits(held) + " m/s: stiffen material.youngs_modulus, or slow the particles");
    }
  } catch (const ConfigError&) {
    // An over-damped contact: refused by the time-step check already.
  }
  // At rest on the floor: the bed's weight over the floor's area, on each bottom sphere's
  // square of side 2R (the largest spheres press in deepest: k_n grows as R, the load as R²).
  const double down = -scene.simulation.gravity.z();
  if (!scene.box.walls[4] || !(down > 0.0)) return;
  const Vec3 size = scene.box.max - scene.box.min;
  const double big = bound.largestRadius;
  const double load =
      material.density * bound.volume * down / (size.x() * size.y()) * (2.0 * big) * (2.0 * big);
  const double kn = material.normalCoefficient();
  const double sunk = material.normalLaw == NormalLaw::Hooke
                          ? load / (kn * big)
                          : std::pow(load / (kn * std::sqrt(big)), 2.0 / 3.0);
  if (sunk > big) {
    scene.warnings.push_back(
        warningPrefix(root, file, "material", "youngs_modulus") + "at rest on the floor, the " +
        "bed's weight (" + fourDigits(material.density * bound.volume * down) + " N over " +
        fourDigits(size.x() * size.y()) + " m²) presses each bottom sphere of radius " +
        fourDigits(big) + " m " + fourDigits(sunk / big) +
        " radii into it: the spheres sink through the floor, whatever the time step; stiffen "
        "material.youngs_modulus");
  }
}

}  // namespace granular
