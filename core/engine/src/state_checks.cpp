/// State integrity checks (state_checks.hpp).
#include "state_checks.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <sstream>

#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/error.hpp"
#include "granular/wall_mesh.hpp"
#include "pair_springs.hpp"
#include "particle_fields.hpp"
#include "wall_motion.hpp"

namespace granular {

namespace {

std::string describe(const Vec3& v) {
  std::ostringstream o;
  o.precision(6);
  o << "(" << v.x() << ", " << v.y() << ", " << v.z() << ")";
  return o.str();
}
std::string describe(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

/// Collects the first problem found; the reader stops at it. A message is composed only for the
/// problem: the checks run per particle, pair and spring (10⁷ of them for 10⁶ Gear5 particles).
class Checker {
 public:
  explicit Checker(const std::string& file) : file_(file) {}
  [[noreturn]] void fail(const std::string& what) const {
    throw CheckpointError(file_ + ": inconsistent checkpoint: " + what);
  }
  void require(bool ok, const char* what) const {
    if (!ok) fail(what);
  }
  /// For checks made once: per element, test first and compose the message in the branch.
  void require(bool ok, const std::string& what) const {
    if (!ok) fail(what);
  }
  void finite(double x, const char* what) const {
    if (!std::isfinite(x)) fail(std::string(what) + " is not finite");
  }
  void positive(double x, const char* what) const {
    if (!(std::isfinite(x) && x > 0)) fail(std::string(what) + " must be finite and > 0");
  }
  void nonNegative(double x, const char* what) const {
    if (!(std::isfinite(x) && x >= 0)) fail(std::string(what) + " must be finite and >= 0");
  }
  void finite(const Vec3& v, const char* what) const {
    if (!v.allFinite()) fail(std::string(what) + " " + describe(v) + " is not finite");
  }
  template <class T>
  void sized(const std::vector<T>& v, std::size_t n, const char* what) const {
    if (v.size() != n) {
      fail(std::string(what) + " has " + std::to_string(v.size()) + " entries, expected " +
           std::to_string(n));
    }
  }

 private:
  const std::string& file_;
};

void checkConfig(const Checker& c, const SimulationState& s) {
  try {  // the declarations' rules, the same as for a scene
    validateMaterial(s.config.material);
  } catch (const ConfigError& e) {
    c.fail(e.what());
  }
  const SimulationConfig& cfg = s.config;
  c.finite(cfg.gravity, "gravity");
  c.require(cfg.integrator == Integrator::Gear5 || cfg.integrator == Integrator::VelocityVerlet,
            "unknown integrator " + std::to_string(int(cfg.integrator)));
  c.positive(cfg.timeStep, "time step");
  c.nonNegative(cfg.skin, "skin");
  c.positive(cfg.impactSpeed, "impact speed");
  c.finite(s.timeOrigin, "clock origin");
  c.require(s.frictional == s.config.material.hasFriction(),
            "friction flag disagrees with the friction");
  c.positive(s.contactScale.duration, "contact duration");
  c.positive(s.contactScale.radius, "contact radius");
}

/// "particle 12: velocity (nan, 0, 0) m/s is not finite".
template <class T>
std::string notFinite(std::uint64_t particle, const FieldSpec& field, const T& value) {
  // A stream, not a chain of +: GCC 12 misreads the chain as overlapping copies (-Wrestrict).
  std::ostringstream o;
  o << "particle " << particle << ": " << field.name << " " << describe(value);
  if (!field.unit.empty()) o << " " << field.unit;
  o << " is not finite";
  return o.str();
}

bool finiteValue(const Vec3& v) {
  return v.allFinite();
}
bool finiteValue(double x) {
  return std::isfinite(x);
}

/// Every per-particle array holds an entry per particle where the state holds the field, and
/// none where it does not (particle_fields.hpp).
void checkFieldSizes(const Checker& c, const SimulationState& s) {
  const std::size_t n = s.particles.size();
  forEachStateField(s, [&](const FieldSpec& field, const auto& values) {
    const std::size_t expected = holds(s, field.needs) ? n : 0;
    if (values.size() != expected) {
      c.fail("the " + std::string(field.name) + " array has " + std::to_string(values.size()) +
             " entries, expected " + std::to_string(expected));
    }
  });
}

void checkParticles(const Checker& c, const SimulationState& s) {
  const Particles& p = s.particles;
  const std::size_t n = p.size();
  c.require(n > 0, "no particles");
  // Pair indices are 32-bit.
  c.require(n < std::numeric_limits<std::uint32_t>::max(), "too many particles");
  checkFieldSizes(c, s);
  if (const std::optional<std::string> bad = firstNonFiniteParticle(p)) c.require(false, *bad);
  for (std::size_t i = 0; i < n; ++i) {
    if (!(std::isfinite(p.radius[i]) && p.radius[i] > 0)) {
      c.fail("particle " + std::to_string(i) + ": radius must be finite and > 0");
    }
    if (!(std::isfinite(p.mass[i]) && p.mass[i] > 0)) {
      c.fail("particle " + std::to_string(i) + ": mass must be finite and > 0");
    }
  }
}

/// The integrator's fields, finite (their sizes are checked with the particles').
void checkMotion(const Checker& c, const SimulationState& s) {
  forEachMotionField(s, [&](const FieldSpec& field, const auto& values) {
    for (std::size_t i = 0; i < values.size(); ++i) {
      if (!finiteValue(values[i])) c.fail(notFinite(i, field, values[i]));
    }
  });
}

void checkWalls(const Checker& c, const SimulationState& s) {
  for (const Wall& w : s.walls) {
    c.finite(w.point, "a wall point");
    c.finite(w.velocity, "a wall velocity");
    c.finite(w.reaction, "a wall reaction");
    c.finite(w.impulse, "a wall impulse");
    c.require(w.normal.allFinite() && std::abs(w.normal.norm() - 1.0) < 1e-12,
              "wall '" + w.name + "': normal is not a unit vector");
    try {
      validateWall(w);
    } catch (const ConfigError& e) {
      c.fail(e.what());
    }
    c.nonNegative(w.travel, "a wall's travel");
  }
}

/// Every slot finite, and each term's own rule for its slots (contact_model.hpp).
void checkHistory(const Checker& c, const ContactHistory& h) {
  for (const double x : h.slot) c.finite(x, "a contact history slot");
  for (const TermSpec& term : contactTerms()) {
    if (!term.historyProblem) continue;
    if (const char* problem = term.historyProblem(h.slot + term.historyOffset)) c.fail(problem);
  }
}
void checkHistory(const Checker& c, const std::vector<ContactHistory>& history) {
  for (const ContactHistory& h : history) checkHistory(c, h);
}

void checkNeighbours(const Checker& c, const SimulationState& s) {
  const NeighbourList& list = s.neighbours;
  const std::size_t n = s.particles.size();
  const std::size_t pairs = list.second.size();
  c.require(
      list.rowStart.size() == n + 1 && list.rowStart.front() == 0 && list.rowStart.back() == pairs,
      "pair list rows do not cover the pairs");
  for (std::size_t i = 0; i < n; ++i) {
    // Rows ascend within the pairs (checked before a row is read), so every k below is a pair.
    c.require(list.rowStart[i] <= list.rowStart[i + 1] && list.rowStart[i + 1] <= pairs,
              "pair list is not sorted");
    for (std::size_t k = list.rowStart[i]; k < list.rowStart[i + 1]; ++k) {
      if (!(i < list.second[k] && list.second[k] < n)) {
        c.fail("pair " + std::to_string(k) + " indexes particles out of range or out of order");
      }
      // Sorted by (first, second) without repeats: the history merge and the gather rely on it.
      c.require(k == list.rowStart[i] || list.second[k - 1] < list.second[k],
                "pair list is not sorted");
    }
  }
  // The particle blocks (derived from the list on loading) and the springs laid out in them.
  const std::size_t blocks = list.blockParticle.size() - 1;
  c.require(!list.blockParticle.empty() && list.blockPair.size() == blocks + 1 &&
                list.blockWord.size() == blocks + 1 && list.blockParticle.back() == n &&
                list.blockPair.back() == pairs,
            "particle blocks do not cover the particles and pairs");
  c.sized(list.springs.held, s.frictional ? list.blockWord.back() : 0, "pair history (words)");
  if (s.frictional) {
    c.sized(list.springs.block, blocks, "pair history blocks");
    for (std::size_t b = 0; b < blocks; ++b) {
      std::size_t held = 0;
      for (std::size_t w = list.blockWord[b]; w < list.blockWord[b + 1]; ++w) {
        held += static_cast<std::size_t>(std::popcount(list.springs.held[w]));
      }
      const PairSprings& springs = list.springs;
      c.require(springs.optional < kHistorySlotsByMask.size() &&
                    springs.slots == historyRecordSlots(springs.optional),
                "pair history records do not match their terms");
      c.sized(springs.block[b], held * springs.slots, "a block of pair history");
      for (std::size_t k = 0; k < held; ++k) {
        checkHistory(c,
                     expandRecord(springs.block[b].data() + k * springs.slots, springs.optional));
      }
    }
  }
  const std::size_t walls = s.walls.size();
  c.sized(list.wallParticles, walls, "wall candidate lists");
  c.sized(list.wallHistory, s.frictional ? walls : 0, "wall histories");
  for (std::size_t w = 0; w < walls; ++w) {
    const std::vector<std::uint32_t>& candidates = list.wallParticles[w];
    // A mesh lists each candidate kMeshContacts times in a row.
    const bool mesh = s.walls[w].shape == WallShape::Mesh;
    const std::size_t group = mesh ? kMeshContacts : 1;
    c.require(candidates.size() % group == 0, "a mesh's candidate list is not in whole groups");
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const bool inGroup = k % group != 0;
      c.require(candidates[k] < n && (k == 0 || (inGroup ? candidates[k - 1] == candidates[k]
                                                         : candidates[k - 1] < candidates[k])),
                "wall candidate list out of range or not sorted");
    }
    if (!s.frictional) continue;
    c.sized(list.wallHistory[w], candidates.size(), "wall history");
    checkHistory(c, list.wallHistory[w]);
    if (mesh) {
      c.require(w < list.wallNormal.size() && list.wallNormal[w].size() == candidates.size(),
                "a mesh's contact normals do not match its candidates");
      for (const Vec3& normal : list.wallNormal[w]) {
        c.require(
            normal.allFinite() && (normal.isZero(0.0) || std::abs(normal.norm() - 1.0) < 1e-9),
            "a mesh contact's normal is neither zero nor a unit vector");
      }
    }
  }
  c.sized(list.referencePosition, list.valid ? n : list.referencePosition.size(),
          "reference positions");
  c.sized(list.referenceWallPoint, list.valid ? walls : list.referenceWallPoint.size(),
          "reference wall points");
  // Infinite is allowed: a position beyond the single-precision range rounds to it (and keeps
  // the list rebuilt every step, neighbour_list.cpp).
  for (const Eigen::Vector3f& x : list.referencePosition) {
    c.require(!x.hasNaN(), "a reference position is NaN");
  }
  for (const Vec3& x : list.referenceWallPoint) c.finite(x, "a reference wall point");
  c.sized(list.referenceWallTravel, list.valid ? walls : list.referenceWallTravel.size(),
          "reference wall travels");
  for (std::size_t w = 0; w < list.referenceWallTravel.size(); ++w) {
    c.require(list.referenceWallTravel[w] >= 0.0 &&
                  (w >= s.walls.size() || list.referenceWallTravel[w] <= s.walls[w].travel),
              "a reference wall travel is negative or ahead of its wall");
  }
  c.nonNegative(list.skin, "skin");
}

void checkEnergy(const Checker& c, const SimulationState& s) {
  const ContactPowers& w = s.powers;
  for (double x : w.energy) c.finite(x, "a contact power");
  c.finite(w.wallPower, "a contact power");
  const EnergyAccumulators& e = s.energy;
  for (double x : e.account) c.finite(x, "an energy account");
  for (double x : e.initialStored) c.finite(x, "an energy account");
  for (double x : {e.wallWork, e.initialPotential}) c.finite(x, "an energy account");
}

}  // namespace

std::optional<std::string> firstNonFiniteParticle(const Particles& p,
                                                  const std::vector<std::uint8_t>* owned,
                                                  const std::vector<std::uint64_t>* ids) {
  const std::size_t n = p.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (owned && !(*owned)[i]) continue;
    std::optional<std::string> found;
    forEachParticleField(p, [&](const FieldSpec& field, const auto& values) {
      if (!found && i < values.size() && !finiteValue(values[i])) {
        found = notFinite(ids ? (*ids)[i] : i, field, values[i]);
      }
    });
    if (found) return found;
  }
  return std::nullopt;
}

void validateRestoredState(const SimulationState& state, const std::string& file) {
  const Checker c(file);
  checkConfig(c, state);
  checkParticles(c, state);
  checkMotion(c, state);
  checkWalls(c, state);
  checkNeighbours(c, state);
  checkEnergy(c, state);
}

}  // namespace granular
