/// The one list of per-particle fields (particle_fields.hpp) and the code it drives: the
/// checkpoint holds each listed field once per particle, the reordering permutes every field,
/// a split run's records carry every field, and the state checks find a broken value in any
/// field by its name.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <tuple>
#include <type_traits>

#include "domain_split.hpp"
#include "granular/bricks.hpp"
#include "granular/checkpoint.hpp"
#include "granular/communicator.hpp"
#include "granular/error.hpp"
#include "granular/spatial_order.hpp"
#include "particle_fields.hpp"
#include "simulation_state.hpp"
#include "state_checks.hpp"

using namespace granular;

namespace {

/// `count` spheres 1 m apart in a row: no pair, no wall, so that a checkpoint's size grows with
/// the particles' own fields and nothing else.
Simulation apart(std::size_t count, Integrator integrator, double friction) {
  Particles p;
  for (std::size_t i = 0; i < count; ++i) {
    p.add(Vec3(double(i), 0, 0), 0.03 + 0.001 * double(i), 2500, Vec3(0.1, 0, 0));
  }
  SimulationConfig cfg;
  cfg.material.friction = friction;
  cfg.integrator = integrator;
  cfg.gravity = Vec3::Zero();
  return Simulation(std::move(p), {}, cfg);
}

/// Bytes a particle's held fields take in `s` (those the checkpoint may hold: no split ones).
std::size_t heldBytesPerParticle(const SimulationState& s) {
  std::size_t bytes = 0;
  forEachStateField(s, [&](const FieldSpec& field, const auto& values) {
    if ((field.needs & kSplit) == 0 && holds(s, field.needs)) bytes += sizeof(values[0]);
  });
  return bytes;
}

/// Calls visit(spec, a's array, b's array) for every per-particle field.
template <class Visit>
void forEachFieldOfBoth(const SimulationState& a, const SimulationState& b, Visit visit) {
  auto each = [&](const auto& list) {
    std::apply(
        [&](const auto&... entry) {
          (visit(entry.spec, arrayOf(entry, a), arrayOf(entry, b)), ...);
        },
        list);
  };
  each(kParticleFields);
  each(kMotionFields);
  each(kSplitFields);
}

/// A value told apart by field and particle: field f, particle i.
void setDistinct(Vec3& v, int f, std::size_t i) {
  const double x = 1000.0 * f + double(i) + 0.5;
  v = Vec3(x, x + 0.25, x + 0.125);
}
void setDistinct(double& v, int f, std::size_t i) {
  v = 1000.0 * f + double(i) + 0.5;
}
template <class T>
void setDistinct(T& v, int f, std::size_t i) {
  v = static_cast<T>(1000 * f + int(i));
}

void plantNaN(Vec3& v) {
  v[1] = std::numeric_limits<double>::quiet_NaN();
}
void plantNaN(double& v) {
  v = std::numeric_limits<double>::quiet_NaN();
}

}  // namespace

TEST(ParticleFields, NamesAreUniqueAndARecordHoldsEveryValueField) {
  std::set<std::string> names;
  std::size_t values = 0;  // doubles of the fields of Vec3 or double
  Simulation sim = apart(3, Integrator::Gear5, 0.3);
  forEachStateField(SimulationAccess::state(sim), [&](const FieldSpec& field, const auto& array) {
    using T = std::remove_cvref_t<decltype(array[0])>;
    EXPECT_TRUE(names.insert(std::string(field.name)).second) << field.name;
    EXPECT_FALSE(field.name.empty());
    if constexpr (std::is_same_v<T, Vec3> || std::is_same_v<T, double>) {
      EXPECT_FALSE(field.unit.empty()) << field.name;
      EXPECT_EQ(field.needs & kSplit, 0u) << field.name;
      values += sizeof(T) / sizeof(double);
    }
  });
  EXPECT_EQ(recordDoubles(), values);
  // The ghosts' message, sent every step: position, velocity, angular velocity and the two
  // accelerations (Verlet's powers' lead) alone.
  EXPECT_EQ(ghostDoubles(), 15u);
}

TEST(ParticleFields, TheCheckpointHoldsEachHeldFieldOncePerParticle) {
  struct Case {
    Integrator integrator;
    double friction;
  };
  for (const Case& c :
       {Case{Integrator::Gear5, 0.3}, Case{Integrator::Gear5, 0.0},
        Case{Integrator::VelocityVerlet, 0.3}, Case{Integrator::VelocityVerlet, 0.0}}) {
    Simulation few = apart(4, c.integrator, c.friction);
    Simulation more = apart(11, c.integrator, c.friction);
    const SimulationState& s = SimulationAccess::state(more);
    // Each field is held, or not, as its line says; a frictional Gear run holds every one
    // but a split run's.
    const bool all = c.integrator == Integrator::Gear5 && c.friction > 0;
    forEachStateField(s, [&](const FieldSpec& field, const auto& values) {
      const bool held = holds(s, field.needs);
      EXPECT_EQ(values.size(), held ? 11u : 0u) << field.name;
      if (all) {
        EXPECT_EQ(held, (field.needs & kSplit) == 0) << field.name;
      }
    });
    const auto dir = std::filesystem::temp_directory_path();
    const auto a = dir / "granular_test_fields_few.ckpt";
    const auto b = dir / "granular_test_fields_more.ckpt";
    writeCheckpoint(few, a, 1);
    writeCheckpoint(more, b, 1);
    // Per particle the file holds the listed fields the state holds and the neighbour list's
    // reference position (3 doubles), nothing else.
    const std::uintmax_t perParticle = heldBytesPerParticle(s) + 3 * sizeof(double);
    EXPECT_EQ(std::filesystem::file_size(b) - std::filesystem::file_size(a), 7 * perParticle);
    // And reads back to the same values, field by field.
    Simulation back = readCheckpoint(b, 1);
    forEachFieldOfBoth(SimulationAccess::state(back), s,
                       [&](const FieldSpec& field, const auto& values, const auto& original) {
                         ASSERT_EQ(values.size(), original.size()) << field.name;
                         for (std::size_t i = 0; i < values.size(); ++i) {
                           EXPECT_TRUE(values[i] == original[i]) << field.name << " of " << i;
                         }
                       });
    std::filesystem::remove(a);
    std::filesystem::remove(b);
  }
}

TEST(ParticleFields, ReorderingPermutesEveryField) {
  Particles p;
  for (std::size_t i = 0; i < 5; ++i) p.add(Vec3::Zero(), 1.0, 1.0);
  int f = 0;
  forEachParticleField(p, [&](const FieldSpec&, auto& values) {
    for (std::size_t i = 0; i < values.size(); ++i) setDistinct(values[i], f, i);
    ++f;
  });
  const std::vector<std::size_t> order = {3, 0, 4, 1, 2};
  Particles q = reordered(p, order);
  EXPECT_EQ(q.size(), 5u);
  forEachParticleFieldPair(p, q, [&](const FieldSpec& field, const auto& from, const auto& to) {
    ASSERT_EQ(to.size(), order.size()) << field.name;
    for (std::size_t k = 0; k < order.size(); ++k) {
      EXPECT_TRUE(to[k] == from[order[k]]) << field.name << " at " << k;
    }
  });
}

TEST(ParticleFields, ASplitRunsRecordsCarryEveryField) {
  // Split on one process, every particle travels as a record (splitState), and back
  // (gatherWhole): each field must come through to the bit.
  Simulation sim = apart(6, Integrator::Gear5, 0.3);
  SimulationState s = SimulationAccess::state(sim);
  int f = 0;
  forEachStateField(s, [&](const FieldSpec& field, auto& values) {
    ++f;
    if (field.name == "position") return;  // x = 0..5 m apart already, inside the brick
    for (std::size_t i = 0; i < values.size(); ++i) setDistinct(values[i], f, i);
  });
  const SimulationState distinct = s;
  const std::shared_ptr<const Communicator> one = singleProcess();
  splitState(s, std::make_shared<Bricks>(1, Vec3(-1, -1, -1), Vec3(7, 1, 1)), one);
  const std::unique_ptr<SimulationState> whole = gatherWhole(s);
  forEachFieldOfBoth(*whole, distinct,
                     [&](const FieldSpec& field, const auto& values, const auto& before) {
                       if ((field.needs & kSplit) != 0) return;  // a whole state has none
                       ASSERT_EQ(values.size(), before.size()) << field.name;
                       for (std::size_t i = 0; i < values.size(); ++i) {
                         EXPECT_TRUE(values[i] == before[i]) << field.name << " of " << i;
                       }
                     });
  // The split state's own bookkeeping: an id and an ownership per particle.
  EXPECT_EQ(s.split.globalId.size(), 6u);
  EXPECT_EQ(s.owned.size(), 6u);
}

TEST(ParticleFields, ANonFiniteValueInAnyFieldIsFoundByName) {
  Simulation sim = apart(5, Integrator::Gear5, 0.3);
  const SimulationState& s = SimulationAccess::state(sim);
  std::size_t count = 0;
  forEachStateField(s, [&](const FieldSpec&, const auto&) { ++count; });
  std::size_t planted = 0;
  for (std::size_t target = 0; target < count; ++target) {
    SimulationState broken = s;
    std::string name;
    std::size_t k = 0;
    forEachStateField(broken, [&](const FieldSpec& field, auto& values) {
      using T = std::remove_cvref_t<decltype(values[0])>;
      if (k++ != target) return;
      if constexpr (std::is_same_v<T, Vec3> || std::is_same_v<T, double>) {
        plantNaN(values[2]);
        name = field.name;
      }
    });
    if (name.empty()) continue;  // an integer field (a split run's) cannot be NaN
    ++planted;
    try {
      validateRestoredState(broken, "planted");
      ADD_FAILURE() << "a NaN in the " << name << " was not found";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("particle 2: " + name + " "), std::string::npos)
          << e.what();
    }
    if (target < std::tuple_size_v<decltype(kParticleFields)>) {
      // A field of Particles: the step's own scan finds it too.
      const std::optional<std::string> found = firstNonFiniteParticle(broken.particles);
      ASSERT_TRUE(found.has_value()) << name;
      EXPECT_EQ(found->rfind("particle 2: " + name + " ", 0), 0u) << *found;
    }
  }
  EXPECT_EQ(planted, count - std::tuple_size_v<decltype(kSplitFields)>);  // all but integers
}

TEST(ParticleFields, AnArrayOfTheWrongLengthIsRefusedByName) {
  Simulation sim = apart(5, Integrator::VelocityVerlet, 0.0);
  const SimulationState& s = SimulationAccess::state(sim);
  std::size_t count = 0;
  forEachStateField(s, [&](const FieldSpec&, const auto&) { ++count; });
  // From 1: the position array gives the particles' count, against which the others are held.
  for (std::size_t target = 1; target < count; ++target) {
    SimulationState broken = s;
    std::string name;
    std::size_t k = 0;
    forEachStateField(broken, [&](const FieldSpec& field, auto& values) {
      if (k++ != target) return;
      values.resize(values.size() + 1);  // one too many, held or not
      setDistinct(values.back(), 0, 0);
      name = field.name;
    });
    try {
      validateRestoredState(broken, "resized");
      ADD_FAILURE() << "a " << name << " array of the wrong length was accepted";
    } catch (const CheckpointError& e) {
      EXPECT_NE(std::string(e.what()).find("the " + name + " array has"), std::string::npos)
          << e.what();
    }
  }
}
