/// runSiloStudy (silo_study.hpp): fill, measure at rest, discharge through each orifice.
#include "granular/silo_study.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "granular/error.hpp"
#include "granular/lateral_ratio.hpp"
#include "granular/principal.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"

namespace granular {

namespace {

/// The silo's walls by the study's names.
struct SiloWalls {
  std::size_t cylinder = 0;
  double radius = 0;
  double floorZ = 0;
  std::vector<std::string> opening;  ///< gate, ring1, ring2, …: taken away in this order
  std::vector<double> orifices;      ///< D₀ of each orifice, ascending [m]
  std::vector<double> outletZ;       ///< each orifice's height: the top of what opens it [m]
  long hopper = -1;                  ///< the conical hopper's wall, or −1
  double transition = 0;             ///< the hopper's top, else the floor [m]
  double hopperBottom = 0;           ///< the hopper's lowest height [m]
  double hopperRadius = 0;           ///< its radius there [m]
};

const Wall& namedWall(const Simulation& sim, const std::string& name) {
  const long index = sim.findWall(name);
  if (index < 0) throw ConfigError("silo study: the scene has no wall named '" + name + "'");
  return sim.walls()[std::size_t(index)];
}

/// The outer radius of a gate or ring: a disc or annulus, or a piece of a hopper's cone, about
/// the silo's axis; taking it away opens an orifice of twice that radius.
double outerRadiusOfOpening(const Wall& w) {
  if (w.shape != WallShape::Frustum || std::abs(w.normal.z()) < 1.0 - 1e-12 ||
      std::abs(w.point.x()) + std::abs(w.point.y()) > 1e-12) {
    throw ConfigError("silo study: wall '" + w.name +
                      "' must be a disc, an annulus or a cone about the silo's axis");
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
  s.orifices.push_back(2.0 * outerRadiusOfOpening(gate));
  s.outletZ.push_back(s.floorZ);
  for (int k = 1; sim.findWall("ring" + std::to_string(k)) >= 0; ++k) {
    const std::string name = "ring" + std::to_string(k);
    s.opening.push_back(name);
    const Wall& ring = namedWall(sim, name);
    s.orifices.push_back(2.0 * outerRadiusOfOpening(ring));
    s.outletZ.push_back(std::max(s.outletZ.back(), ring.point.z() + ring.length * ring.normal.z()));
  }
  s.transition = s.floorZ;
  s.hopper = sim.findWall("hopper");
  if (s.hopper >= 0) {
    const Wall& h = sim.walls()[std::size_t(s.hopper)];
    const double scale = std::max(1.0, s.radius);
    if (h.shape != WallShape::Frustum || !(h.length > 0.0) || h.normal.z() < 1.0 - 1e-12 ||
        std::abs(h.point.x()) + std::abs(h.point.y()) > 1e-12 * scale ||
        h.point.z() < s.floorZ - 1e-9 * scale || std::abs(h.radiusEnd - s.radius) > 1e-9 * scale ||
        !(h.radiusStart < h.radiusEnd) || 2.0 * h.radiusStart < s.orifices.back() * (1.0 - 1e-9)) {
      throw ConfigError(
          "silo study: wall 'hopper' must be a cone with axis [0, 0, 1] on the silo's axis, "
          "from the floor or above, where its radius is the largest orifice's or more, to the "
          "cylinder's radius");
    }
    s.hopperBottom = h.point.z();
    s.transition = s.hopperBottom + h.length;
    s.hopperRadius = h.radiusStart;
  }
  return s;
}

/// What one sample of the bed gives per level.
struct LevelSample {
  std::vector<WallContact> wall;
  std::vector<WallContact> hopper;
  std::vector<SliceContact> slices;
  std::vector<double> mass;  ///< per level: the particles whose centres are in it [kg]
};

LevelSample sampleBed(const Simulation& sim, std::size_t cylinder, long hopper,
                      const std::vector<double>& edges) {
  LevelSample out;
  out.mass.assign(edges.size() - 1, 0.0);
  const Particles& p = sim.particles();
  sim.forEachContact([&](const ContactView& c) {
    if (!c.touching()) return;
    const Vec3& x = p.position[c.particle];
    out.slices.push_back({x.z(), c.force.z(), c.point.z() - x.z()});
    if (!c.isWall() || (c.wall() != cylinder && long(c.wall()) != hopper)) return;
    const Vec3 onWall = -c.force;  // the particle's push on the wall
    const double normal = onWall.dot(c.normal);
    const Vec3 tangential = onWall - normal * c.normal;
    const WallContact contact{c.point.z(), std::max(normal, 0.0), tangential.norm(), onWall.z()};
    (c.wall() == cylinder ? out.wall : out.hopper).push_back(contact);
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

/// The flowing material above an orifice, in one sample of a sphere.
struct FlowZone {
  double angle = 0;    ///< the angle of internal friction of its stress, NaN if none [rad]
  double density = 0;  ///< the mass of the particles whose centres it holds over its volume
};

/// Eq. (1)'s stress over the sphere at `centre` of `radius`, from the particles' own stresses
/// (particleStresses: Σ_i V_i σ^i over its members is Eq. (1)'s sum), as an angle of internal
/// friction (internalFrictionAngleFromStresses; NaN where the sphere holds no compressed
/// particle or is in tension), and its bulk density.
FlowZone flowZoneIn(const Simulation& sim, const std::vector<Mat3>& stresses, const Vec3& centre,
                    double radius) {
  const Particles& p = sim.particles();
  Mat3 sum = Mat3::Zero();
  double mass = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if ((p.position[i] - centre).squaredNorm() > radius * radius) continue;
    const double r = p.radius[i];
    sum += (4.0 / 3.0 * std::numbers::pi * r * r * r) * stresses[i];
    mass += p.mass[i];
  }
  FlowZone zone;
  zone.density = mass / (4.0 / 3.0 * std::numbers::pi * radius * radius * radius);
  // Compression is negative in Eq. (1): σ1, the most compressive, is the smallest value.
  const Vec3 principal = principalStresses(sum).values;
  zone.angle = !(principal.x() < 0.0) || principal.z() > 0.0
                   ? std::nan("")
                   : internalFrictionAngleFromStresses(-principal.x(), -principal.z());
  return zone;
}

/// The mean of per-sample values (one vector of `size` per sample) over the discharge's steady
/// window; zeros when it did not flow.
std::vector<double> steadyWindowMean(const SiloDischarge& discharge,
                                     const std::vector<std::vector<double>>& perSample,
                                     std::size_t size) {
  std::vector<double> mean(size, 0.0);
  std::size_t used = 0;
  for (std::size_t s = 0; s < perSample.size(); ++s) {
    const double t = discharge.time[s];
    if (!discharge.flowed || t < discharge.steady.t0 || t > discharge.steady.t1) continue;
    for (std::size_t l = 0; l < size; ++l) mean[l] += perSample[s][l];
    ++used;
  }
  for (double& x : mean) x /= double(std::max<std::size_t>(used, 1));
  return mean;
}

}  // namespace

SiloStudyResult runSiloStudy(const Scene& scene, const SiloStudyOptions& options) {
  if (scene.stages.empty()) throw ConfigError("silo study: the scene has no fill stage");
  SiloStudyResult result;
  Simulation sim = buildSimulation(scene);
  const SiloWalls walls = siloWalls(sim);
  result.radius = walls.radius;
  result.floor = walls.floorZ;
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
  if (!(top > walls.transition + 4.0 * band)) {
    throw ConfigError("silo study: the bed is too shallow to measure (under four bands above " +
                      std::string(walls.hopper >= 0 ? "the hopper" : "the floor") + ")");
  }
  std::vector<double> edges;
  for (double z = walls.transition; z < top; z += band) edges.push_back(z);
  edges.push_back(edges.back() + band);
  const std::size_t levels = edges.size() - 1;
  WallBandAverage wall(edges, cylinderBandAreas(walls.radius, edges));
  std::vector<double> sigmaV(levels, 0.0), mass(levels, 0.0);
  // The hopper's wall in bands of about the same height, its top edge at the transition.
  result.transition = walls.transition;
  std::vector<double> hopperEdges;
  if (walls.hopper >= 0) {
    result.hasHopper = true;
    const double height = walls.transition - walls.hopperBottom;
    result.hopperHalfAngle = std::atan((walls.radius - walls.hopperRadius) / height);
    const long count = std::max(1L, std::lround(height / band));
    for (long k = 0; k <= count; ++k) {
      hopperEdges.push_back(k == count ? walls.transition
                                       : walls.hopperBottom + height * double(k) / double(count));
    }
  }
  const auto hopperAreas = [&] {
    return frustumBandAreas(walls.hopperBottom, walls.hopperRadius, walls.transition, walls.radius,
                            hopperEdges);
  };
  std::optional<WallBandAverage> hopperWall;
  if (result.hasHopper) hopperWall.emplace(hopperEdges, hopperAreas());
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
        const LevelSample sample = sampleBed(s, walls.cylinder, walls.hopper, edges);
        wall.addSample(sample.wall);
        if (hopperWall) hopperWall->addSample(sample.hopper);
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
  if (hopperWall) {
    for (const WallBandStats& b : hopperWall->bands()) {
      result.hopperBands.push_back({b.zLow, b.zHigh, b.meanPressure, b.pressureStd});
    }
  }
  // The surface: the height the cylinder's part of the bed reaches at the bulk density of its
  // middle (the levels a band clear of the floor or the transition and two below the highest
  // particle), which the uneven free surface does not bias.
  double middleMass = 0.0, middleVolume = 0.0, cylinderMass = 0.0;
  for (const SiloLevel& level : result.levels) {
    cylinderMass += level.bulkDensity * section * band;
    if (level.zLow >= walls.transition + band && level.zHigh <= top - 2.0 * band) {
      middleMass += level.bulkDensity * section * band;
      middleVolume += section * band;
    }
  }
  if (!(middleVolume > 0.0)) {
    throw ConfigError("silo study: the bed is too shallow to measure (under four bands)");
  }
  result.bulkDensity = middleMass / middleVolume;
  result.surface = walls.transition + cylinderMass / (result.bulkDensity * section);
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
    level.inBed = level.zHigh <= result.surface - band && level.zLow >= walls.transition + band;
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

  if (options.onSettled) options.onSettled(sim, result);

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
    std::optional<WallBandAverage> hopperPerSample;
    if (result.hasHopper) hopperPerSample.emplace(hopperEdges, hopperAreas());
    std::vector<std::vector<double>> pressures, hopperPressures;
    std::vector<FlowZone> flowZones;
    const double start = run.time();
    runSampled(
        run, stage, options.dischargeTime, options.sampleInterval,
        [&](const Simulation& s) {
          discharge.time.push_back(s.time() - start);
          discharge.discharged.push_back(s.particleTally().removedMass);
          const LevelSample sample = sampleBed(s, walls.cylinder, walls.hopper, edges);
          pressures.push_back(perSample.addSample(sample.wall).pressure);
          flowZones.push_back(flowZoneIn(s, particleStresses(s),
                                         Vec3(0.0, 0.0, walls.outletZ[k] + discharge.orifice),
                                         discharge.orifice / 3.0));
          if (hopperPerSample) {
            hopperPressures.push_back(hopperPerSample->addSample(sample.hopper).pressure);
          }
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
    discharge.wallPressure = steadyWindowMean(discharge, pressures, levels);
    discharge.internalFriction = discharge.flowDensity = std::nan("");
    double angleSum = 0.0, densitySum = 0.0;
    std::size_t angles = 0, densities = 0;
    for (std::size_t s = 0; s < flowZones.size() && discharge.flowed; ++s) {
      const double t = discharge.time[s];
      if (t < discharge.steady.t0 || t > discharge.steady.t1) continue;
      densitySum += flowZones[s].density;
      ++densities;
      if (!std::isfinite(flowZones[s].angle)) continue;
      angleSum += flowZones[s].angle;
      ++angles;
    }
    if (angles > 0) discharge.internalFriction = angleSum / double(angles);
    if (densities > 0) discharge.flowDensity = densitySum / double(densities);
    if (result.hasHopper) {
      discharge.hopperPressure =
          steadyWindowMean(discharge, hopperPressures, hopperEdges.size() - 1);
    }
    result.discharges.push_back(std::move(discharge));
  }

  // 4. Beverloo over the orifices that flowed; the flowing material's angle of friction.
  std::vector<double> orifices, rates;
  double frictionSum = 0.0;
  std::size_t frictionCount = 0;
  for (const SiloDischarge& d : result.discharges) {
    if (!d.flowed) continue;
    orifices.push_back(d.orifice);
    rates.push_back(d.steady.rate);
    if (std::isfinite(d.internalFriction)) {
      frictionSum += d.internalFriction;
      ++frictionCount;
    }
  }
  result.internalFriction = frictionCount > 0 ? frictionSum / double(frictionCount) : std::nan("");
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
