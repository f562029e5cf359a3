/// runSiloStudy (silo_study.hpp): fill, measure at rest, discharge through each orifice.
#include "granular/silo_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "granular/error.hpp"
#include "granular/stage.hpp"

namespace granular {

namespace {

/// The silo's walls by the study's names.
struct SiloWalls {
  std::size_t cylinder = 0;
  double radius = 0;
  double floorZ = 0;
  std::vector<std::string> opening;  ///< gate, ring1, ring2, …: taken away in this order
  std::vector<double> orifices;      ///< D₀ of each orifice, ascending [m]
};

const Wall& namedWall(const Simulation& sim, const std::string& name) {
  const long index = sim.findWall(name);
  if (index < 0) throw ConfigError("silo study: the scene has no wall named '" + name + "'");
  return sim.walls()[std::size_t(index)];
}

/// A flat annulus or disc about the silo's axis (a frustum of no length).
double outerRadiusOfFlat(const Wall& w) {
  if (w.shape != WallShape::Frustum || w.length != 0.0) {
    throw ConfigError("silo study: wall '" + w.name + "' must be a disc or an annulus");
  }
  return std::max(w.radiusStart, w.radiusEnd);
}

SiloWalls siloWalls(const Simulation& sim) {
  SiloWalls s;
  const Wall& cylinder = namedWall(sim, "wall");
  if (cylinder.shape != WallShape::Frustum || cylinder.radiusStart != cylinder.radiusEnd ||
      cylinder.normal.z() < 1.0 - 1e-12) {
    throw ConfigError("silo study: wall 'wall' must be a cylinder with axis [0, 0, 1]");
  }
  s.cylinder = std::size_t(sim.findWall("wall"));
  s.radius = cylinder.radiusStart;
  const Wall& gate = namedWall(sim, "gate");
  s.floorZ = gate.point.z();
  s.opening.push_back("gate");
  s.orifices.push_back(2.0 * outerRadiusOfFlat(gate));
  for (int k = 1; sim.findWall("ring" + std::to_string(k)) >= 0; ++k) {
    const std::string name = "ring" + std::to_string(k);
    s.opening.push_back(name);
    s.orifices.push_back(2.0 * outerRadiusOfFlat(namedWall(sim, name)));
  }
  return s;
}

/// What one sample of the bed gives per level.
struct LevelSample {
  std::vector<WallContact> wall;
  std::vector<SliceContact> slices;
  std::vector<double> mass;  ///< per level: the particles whose centres are in it [kg]
};

LevelSample sampleBed(const Simulation& sim, std::size_t cylinder,
                      const std::vector<double>& edges) {
  LevelSample out;
  out.mass.assign(edges.size() - 1, 0.0);
  const Particles& p = sim.particles();
  sim.forEachContact([&](const ContactView& c) {
    if (!c.touching()) return;
    const Vec3& x = p.position[c.particle];
    out.slices.push_back({x.z(), c.force.z(), c.point.z() - x.z()});
    if (c.isWall() && c.wall() == cylinder) {
      const Vec3 onWall = -c.force;  // the particle's push on the wall
      const double normal = onWall.dot(c.normal);
      const Vec3 tangential = onWall - normal * c.normal;
      out.wall.push_back({c.point.z(), std::max(normal, 0.0), tangential.norm(), onWall.z()});
    }
  });
  for (std::size_t i = 0; i < p.size(); ++i) {
    const double z = p.position[i].z();
    const auto at = std::upper_bound(edges.begin(), edges.end(), z);
    if (at == edges.begin() || at == edges.end()) continue;
    out.mass[std::size_t(at - edges.begin()) - 1] += p.mass[i];
  }
  return out;
}

double meanDiameter(const Particles& p) {
  double sum = 0.0;
  for (double r : p.radius) sum += 2.0 * r;
  return p.size() ? sum / double(p.size()) : 0.0;
}

/// Steps `sim` for `duration` [s] under `stage` (its exchanges and gates included), calling
/// `sample` at every `interval` of stage time from the start.
void runSampled(Simulation& sim, StageSpec stage, double duration, double interval,
                const std::function<void(const Simulation&)>& sample,
                const std::function<void(const Simulation&)>& progress) {
  stage.end.maxTime = duration;
  OutputSpec output;
  output.interval = interval;
  StageObserver observer;
  observer.onSample = sample;
  if (progress) {
    observer.progressSteps = 500;
    observer.onProgress = [&](const Simulation& s, const StageSpec&) { progress(s); };
  }
  runStage(sim, stage, output, observer);
}

}  // namespace

SiloStudyResult runSiloStudy(const Scene& scene, const SiloStudyOptions& options) {
  if (scene.stages.empty()) throw ConfigError("silo study: the scene has no fill stage");
  SiloStudyResult result;
  Simulation sim = buildSimulation(scene);
  const SiloWalls walls = siloWalls(sim);
  result.radius = walls.radius;
  auto progress = [&](const std::string& phase) {
    return [&options, phase](const Simulation& s) {
      if (options.onProgress) options.onProgress(s, phase);
    };
  };

  // 1. Fill: the scene's first stage.
  const auto started = std::chrono::steady_clock::now();
  {
    StageObserver observer;
    observer.progressSteps = 500;
    observer.onProgress = [&](const Simulation& s, const StageSpec&) { progress("fill")(s); };
    OutputSpec output = scene.output;
    runStage(sim, scene.stages[0], output, observer);
  }
  result.fillSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  const Particles& p = sim.particles();
  if (p.size() == 0) throw ConfigError("silo study: the fill stage left no particle");
  result.particleDiameter = meanDiameter(p);
  for (double m : p.mass) result.bedMass += m;
  double top = walls.floorZ;
  for (std::size_t i = 0; i < p.size(); ++i) {
    top = std::max(top, p.position[i].z() + p.radius[i]);
  }

  // 2. The wall lifted past the bed (its friction mobilised at every height), then at rest:
  // bands of the wall and slices of the section at the same heights.
  const double band = options.bandHeight > 0 ? options.bandHeight : 2.0 * result.particleDiameter;
  std::vector<double> edges;
  for (double z = walls.floorZ; z < top; z += band) edges.push_back(z);
  edges.push_back(edges.back() + band);
  const std::size_t levels = edges.size() - 1;
  WallBandAverage wall(edges, cylinderBandAreas(walls.radius, edges));
  std::vector<double> sigmaV(levels, 0.0), mass(levels, 0.0);
  if (options.wallLift > 0.0) {
    if (!(options.wallLiftSpeed > 0.0)) {
      throw ConfigError("silo study: the wall's lift speed must be > 0 m/s");
    }
    result.wallLift = options.wallLift * result.particleDiameter;
    StageSpec lift;
    lift.name = "lift";
    lift.wallMotions.push_back({"wall", Vec3(0.0, 0.0, options.wallLiftSpeed)});
    runSampled(sim, lift, result.wallLift / options.wallLiftSpeed, options.sampleInterval, {},
               progress("lift"));
  }
  StageSpec rest;
  rest.name = "rest";
  runSampled(
      sim, rest, options.restWindow, options.sampleInterval,
      [&](const Simulation& s) {
        const LevelSample sample = sampleBed(s, walls.cylinder, edges);
        wall.addSample(sample.wall);
        const SliceStressProfile profile = cylinderSliceStress(sample.slices, walls.radius, edges);
        for (std::size_t k = 0; k < levels; ++k) {
          sigmaV[k] += profile.slices[k].sigmaV;
          mass[k] += sample.mass[k];
        }
        ++result.restSamples;
      },
      progress("rest"));
  const double n = double(std::max<std::size_t>(result.restSamples, 1));
  const double section = std::numbers::pi * walls.radius * walls.radius;
  const std::vector<WallBandStats> bands = wall.bands();
  result.levels.resize(levels);
  for (std::size_t k = 0; k < levels; ++k) {
    SiloLevel& level = result.levels[k];
    level.zLow = edges[k];
    level.zHigh = edges[k + 1];
    level.wallPressure = bands[k].meanPressure;
    level.wallPressureStd = bands[k].pressureStd;
    level.wallShear = -bands[k].meanVerticalShear;  // the wall holds the bed up: > 0
    level.verticalStress = sigmaV[k] / n;
    level.bulkDensity = mass[k] / n / (section * band);
  }
  // The surface: the bed's height at the bulk density of its middle (the levels a band clear of
  // the floor and two below the highest particle), which the uneven free surface does not bias.
  double middleMass = 0.0, middleVolume = 0.0;
  for (const SiloLevel& level : result.levels) {
    if (level.zLow >= walls.floorZ + band && level.zHigh <= top - 2.0 * band) {
      middleMass += level.bulkDensity * section * band;
      middleVolume += section * band;
    }
  }
  if (!(middleVolume > 0.0)) {
    throw ConfigError("silo study: the bed is too shallow to measure (under four bands)");
  }
  result.bulkDensity = middleMass / middleVolume;
  result.surface = walls.floorZ + result.bedMass / (result.bulkDensity * section);
  std::vector<double> depths, stresses;
  double shearSum = 0.0, stressSum = 0.0, kSum = 0.0, muSum = 0.0;
  std::size_t inBed = 0;
  for (SiloLevel& level : result.levels) {
    level.depth = result.surface - 0.5 * (level.zLow + level.zHigh);
    level.lateralRatio =
        level.verticalStress > 0 ? level.wallPressure / level.verticalStress : std::nan("");
    level.mobilisedFriction =
        level.wallPressure > 0 ? level.wallShear / level.wallPressure : std::nan("");
    // In the bed: a band clear of the floor (the layering a flat floor orders) and of the
    // surface (rough at the particles' scale, where a slice is not yet filled and its depth is
    // uncertain by a radius, a large fraction of so small a depth).
    level.inBed = level.zHigh <= result.surface - band && level.zLow >= walls.floorZ + band;
    if (!level.inBed) continue;
    depths.push_back(level.depth);
    stresses.push_back(level.verticalStress);
    shearSum += level.wallShear;
    stressSum += level.verticalStress;
    kSum += level.lateralRatio;
    muSum += level.mobilisedFriction;
    ++inBed;
  }
  const double g = scene.simulation.gravity.norm();
  result.gravity = g;
  if (inBed >= 3) {
    const double rh = circleHydraulicRadius(2.0 * walls.radius);
    result.janssen = fitJanssen(depths, stresses, rh, result.bulkDensity * g);
    result.janssenBoth = fitJanssenLambdaAndGamma(depths, stresses, rh);
    // Janssen's slice balance summed over the bed's levels (of equal height): the wall's
    // shear carries λ times the vertical stress, Σ τ_w = λ Σ σ_v.
    result.lambdaMeasured = shearSum / stressSum;
    result.lateralRatio = kSum / double(inBed);
    result.mobilisedFriction = muSum / double(inBed);
  }

  // 3. Each orifice from the same settled bed.
  const Simulation settled = sim.wholeState();
  for (std::size_t k = 0; k < walls.orifices.size(); ++k) {
    Simulation run = settled.wholeState();
    SiloDischarge discharge;
    discharge.orifice = walls.orifices[k];
    StageSpec stage;
    stage.name = "orifice " + std::to_string(k + 1);
    stage.removeWalls.assign(walls.opening.begin(), walls.opening.begin() + std::ptrdiff_t(k + 1));
    OutletSpec outlet;
    outlet.name = "below";
    outlet.region.min = Vec3(scene.box.min.x(), scene.box.min.y(), scene.box.min.z());
    outlet.region.max =
        Vec3(scene.box.max.x(), scene.box.max.y(), walls.floorZ - 2.0 * result.particleDiameter);
    if (!(outlet.region.max.z() > outlet.region.min.z())) {
      throw ConfigError("silo study: the box must reach two particle diameters below the floor");
    }
    stage.outlets.push_back(outlet);
    stage.exchangeInterval = options.sampleInterval;
    WallBandAverage perSample(edges, cylinderBandAreas(walls.radius, edges));
    std::vector<std::vector<double>> pressures;
    const double start = run.time();
    runSampled(
        run, stage, options.dischargeTime, options.sampleInterval,
        [&](const Simulation& s) {
          discharge.time.push_back(s.time() - start);
          discharge.discharged.push_back(s.particleTally().removedMass);
          pressures.push_back(
              perSample.addSample(sampleBed(s, walls.cylinder, edges).wall).pressure);
        },
        progress("orifice " + std::to_string(k + 1) + " of " +
                 std::to_string(walls.orifices.size())));
    try {
      discharge.steady = steadyDischargeRate(discharge.time, discharge.discharged, 0.2, 0.8);
      // Steady: a window of ten samples or more, and still flowing at half that rate or more
      // over the last quarter of the discharge (an orifice that arched and stopped did not).
      const double end = discharge.time.back();
      const SteadyRate last =
          steadyDischargeRateInWindow(discharge.time, discharge.discharged, 0.75 * end, end);
      discharge.flowed = discharge.steady.samples >= 10 && discharge.steady.rate > 0.0 &&
                         last.rate >= 0.5 * discharge.steady.rate;
    } catch (const std::invalid_argument&) {
      discharge.flowed = false;
    }
    discharge.wallPressure.assign(levels, 0.0);
    std::size_t used = 0;
    for (std::size_t s = 0; s < pressures.size(); ++s) {
      const double t = discharge.time[s];
      if (!discharge.flowed || t < discharge.steady.t0 || t > discharge.steady.t1) continue;
      for (std::size_t l = 0; l < levels; ++l) discharge.wallPressure[l] += pressures[s][l];
      ++used;
    }
    for (double& x : discharge.wallPressure) x /= double(std::max<std::size_t>(used, 1));
    result.discharges.push_back(std::move(discharge));
  }

  // 4. Beverloo over the orifices that flowed.
  std::vector<double> orifices, rates;
  for (const SiloDischarge& d : result.discharges) {
    if (!d.flowed) continue;
    orifices.push_back(d.orifice);
    rates.push_back(d.steady.rate);
  }
  if (orifices.size() >= 2) {
    try {
      result.beverloo =
          fitBeverloo(orifices, rates, result.bulkDensity, g, result.particleDiameter);
      result.beverlooFitted = true;
    } catch (const std::invalid_argument&) {
      result.beverlooFitted = false;
    }
  }
  return result;
}

}  // namespace granular
