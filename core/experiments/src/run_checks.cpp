/// RunChecks (run_checks.hpp): the energy balance and particles outside the box, at samples.
#include "granular/run_checks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "granular/contact_theory.hpp"
#include "number_format.hpp"

namespace granular {
namespace {

std::string fixed(const char* format, double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, format, x);
  return buffer;
}

/// "at t = 0.51 s, step 3000 (stage settle)": where in the run a check failed.
std::string where(const Simulation& sim, const std::string& stage) {
  return "at t = " + fixed("%.9g", sim.time()) + " s, step " + std::to_string(sim.stepCount()) +
         " (stage " + stage + ")";
}

/// A plane bounding the box: a point on it, its normal into the box, and what it is.
struct Bound {
  Vec3 point, normal;
  std::string name;
  bool wall;
  Vec3 velocity = Vec3::Zero();  ///< a wall's [m/s]
};

/// Why particle i passed through a wall: a step that carried it past (tunnelling), or a
/// contact too soft for the speed or the load it met (an overlap beyond its radius), which no
/// step mends.
std::string throughWall(const Simulation& sim, std::size_t i, const Bound& b) {
  const Particles& p = sim.particles();
  const double radius = p.radius[i], mass = p.mass[i];
  const double speed = (p.velocity[i] - b.velocity).dot(-b.normal);  // > 0: on into the wall
  const double dt = sim.config().timeStep;
  if (speed * dt > 0.5 * radius) {
    return "it moves " + fixed("%.3g", speed * dt) + " m a step (" + fixed("%.4g", speed) +
           " m/s × " + fixed("%.3g", dt) +
           " s), more than half its radius: too fast for the time step";
  }
  const double held = speedForPeakOverlap(sim.config().material, radius, mass, radius);
  return "pressed more than its radius into the wall, a sphere passes through it, whatever the "
         "time step: the contact is too soft for the speed or the load it met (this material "
         "holds a head-on impact of a sphere of this radius on a wall up to " +
         fixed("%.4g", held) + " m/s" +
         (speed > held ? ", and the particle still moves at " + fixed("%.4g", speed) + " m/s"
                       : std::string()) +
         "); stiffen material.youngs_modulus, or slow the particles";
}

/// The first of this rank's particles wholly beyond a bound, described; empty if none.
std::string firstOutside(const Simulation& sim, const std::string& stage,
                         const std::vector<Bound>& bounds) {
  const Particles& p = sim.particles();
  // With walls of other shapes the way out may be an opening they leave or a gap in a mesh.
  const bool shells =
      std::any_of(sim.walls().begin(), sim.walls().end(), [](const Wall& w) { return w.shell(); });
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (!sim.owns(i)) continue;
    for (const Bound& b : bounds) {
      const double beyond = -(p.position[i] - b.point).dot(b.normal);  // > R: wholly past it
      if (!(beyond > p.radius[i])) continue;
      const Vec3& x = p.position[i];
      return "particle " + std::to_string(sim.globalId(i)) + " is outside the box " +
             where(sim, stage) + ": centre (" + formatNumber(x.x()) + ", " + formatNumber(x.y()) +
             ", " + formatNumber(x.z()) + ") m, radius " + formatNumber(p.radius[i]) +
             " m, wholly beyond " + b.name + " (its centre " + fixed("%.3g", beyond) +
             " m past it): " +
             (b.wall   ? throughWall(sim, i, b)
              : shells ? "it left past the scene's walls, through an opening or a gap between "
                         "them or in a mesh, and through a face of the box that is not a wall"
                       : "it left through a face that is not a wall");
    }
  }
  return {};
}

}  // namespace

RunChecks::RunChecks(const RunCheckSpec& spec, const BoxSpec& box, double referenceTotal)
    : spec_(spec), box_(box), referenceTotal_(referenceTotal) {}

double RunChecks::workDone(const EnergyBalance& e, double referenceTotal) {
  double work = std::abs(referenceTotal) + std::abs(e.gravityWork) + std::abs(e.wallWork);
  for (const EnergyAccount& a : e.contact) {
    if (a.kind != EnergyKind::Stored) work += std::abs(a.value);  // put in or taken out
  }
  return work;
}

std::vector<std::string> RunChecks::atSample(const Simulation& sim, const std::string& stage) {
  std::vector<std::string> found;
  if (!driftReported_) {
    std::string drift = energyDrift(sim, stage);
    if (!drift.empty()) {
      driftReported_ = true;
      found.push_back(std::move(drift));
    }
  }
  if (!outsideReported_) {
    std::string outside = outsideBox(sim, stage);
    if (!outside.empty()) {
      outsideReported_ = true;
      found.push_back(std::move(outside));
    }
  }
  if (!found.empty() && spec_.onFailedCheck == CheckAction::Stop) {
    throw RunCheckError(found.size() == 1 ? found[0] : found[0] + "; and " + found[1]);
  }
  return found;
}

std::string RunChecks::energyDrift(const Simulation& sim, const std::string& stage) const {
  const EnergyBalance e = sim.energy();
  const double drift = e.total() - referenceTotal_;
  const double work = workDone(e, referenceTotal_);
  // Nothing moved and nothing was stored: the drift is exactly 0 and is never reported.
  if (!(std::abs(drift) > spec_.energyDriftLimit * work)) return {};
  return "energy balance drifted by " + fixed("%+.3g", drift) + " J (" +
         fixed("%.3g", 100.0 * std::abs(drift) / work) + " % of the work done, limit " +
         fixed("%.3g", 100.0 * spec_.energyDriftLimit) + " %) " + where(sim, stage) +
         ": the time step or a damping coefficient is probably too large";
}

std::string RunChecks::outsideBox(const Simulation& sim, const std::string& stage) const {
  // The walls where they are now (a moving wall, the top placed by a stage), and the faces of
  // the box that are not walls but bound where particles start: the sides and the floor.
  std::vector<Bound> bounds;
  // (A shell wall bounds no half-space: the planes and the box do.)
  for (const Wall& w : sim.walls()) {
    if (!w.shell()) bounds.push_back({w.point, w.normal, "the wall " + w.name, true, w.velocity});
  }
  for (std::size_t face = 0; face + 1 < kBoxWallNames.size(); ++face) {
    if (box_.walls[face] || sim.findWall(kBoxWallNames[face]) >= 0) continue;
    const int axis = int(face / 2);
    const bool lower = face % 2 == 0;
    Vec3 normal = Vec3::Zero();
    normal[axis] = lower ? 1.0 : -1.0;
    bounds.push_back({lower ? box_.min : box_.max, normal,
                      std::string("the open face ") + kBoxWallNames[face] + " of the box", false});
  }
  // A split run: each rank looks at its own particles, and every rank takes the lowest rank's
  // finding.
  const std::string found = firstOutside(sim, stage, bounds);
  const Communicator* ranks = sim.ranks();
  return ranks ? ranks->firstOverRanks(found) : found;
}

}  // namespace granular
