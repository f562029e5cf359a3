/// fingerprintScene (scene_fingerprint.hpp). Every struct of the scene is taken apart with a
/// structured binding that names all its members: a member added to one of them stops this file
/// from compiling until it is either fingerprinted or said not to change the run. The material
/// is hashed from the contact model's table (granular/contact_model.hpp), so every declared
/// parameter is in it.
#include "granular/scene_fingerprint.hpp"

#include <algorithm>
#include <cstring>
#include <iterator>
#include <string>
#include <type_traits>

#include "fnv1a.hpp"
#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/error.hpp"
#include "granular/wall_mesh.hpp"
#include "particle_csv.hpp"

namespace granular {

namespace {

/// The canonical bytes of a part: fixed-width numbers (doubles by their bits, so 0.1 written
/// as 1e-1 is the same and -0.0 is not 0.0), strings with their length.
class Canonical {
 public:
  Canonical& operator<<(double x) { return raw(x); }
  Canonical& operator<<(bool x) { return raw(static_cast<unsigned char>(x)); }
  Canonical& operator<<(std::uint64_t x) { return raw(x); }
  Canonical& operator<<(int x) { return raw(static_cast<std::int64_t>(x)); }
  Canonical& operator<<(const Vec3& v) { return *this << v.x() << v.y() << v.z(); }
  Canonical& operator<<(const std::string& s) {
    *this << std::uint64_t(s.size());
    bytes_ += s;
    return *this;
  }
  Canonical& operator<<(const std::optional<double>& x) {
    *this << x.has_value();
    return x ? *this << *x : *this;
  }
  template <class E>
  requires std::is_enum_v<E> Canonical& operator<<(E e) {
    return *this << static_cast<std::int64_t>(e);
  }
  std::uint64_t hash() const { return fnv1a(bytes_); }

 private:
  Canonical& operator<<(std::int64_t x) { return raw(x); }
  template <class T>
  Canonical& raw(const T& value) {
    char buffer[sizeof(T)];
    std::memcpy(buffer, &value, sizeof(T));
    bytes_.append(buffer, sizeof(T));
    return *this;
  }
  std::string bytes_;
};

/// The material as files before the contact model's table hashed it, so that their checkpoints
/// still match: these nine in this order, each as its type (a law as an enum, a flag as a byte).
constexpr std::string_view kFirstParameters[] = {
    "youngs_modulus", "poisson_ratio",      "shear_modulus", "density", "friction",
    "normal_damping", "tangential_damping", "normal_law",    "no_pull"};

std::uint64_t materialHash(const Material& m) {
  Canonical c;
  for (std::string_view key : kFirstParameters) {
    const ParameterSpec& p = *findParameter(key);
    const double value = p.get(m);
    if (p.kind == ParameterKind::Choice) {
      c << static_cast<int>(value);  // as the enum was: its value as 64 bits
    } else if (p.kind == ParameterKind::Flag) {
      c << (value != 0.0);
    } else {
      c << value;
    }
  }
  // Every other declared parameter by key and value, where it differs from its default: a term
  // added with its default (off) leaves every existing scene's fingerprint as it was.
  for (const ParameterSpec& p : materialParameters()) {
    if (std::find(std::begin(kFirstParameters), std::end(kFirstParameters), p.key) !=
        std::end(kFirstParameters)) {
      continue;
    }
    const double value = p.get(m);
    if (std::memcmp(&value, &p.defaultValue, sizeof value) != 0) c << std::string(p.key) << value;
  }
  return c.hash();
}

std::uint64_t boxHash(const BoxSpec& box) {
  const auto& [min, max, walls] = box;
  Canonical c;
  c << min << max;
  for (bool wall : walls) c << wall;
  return c.hash();
}

/// A wall's shape, geometry and motion at the start (its reaction is the run's).
std::uint64_t wallHash(const Wall& w) {
  Canonical c;
  c << w.name << w.shape << w.point << w.normal << w.velocity << w.edge << w.halfSide[0]
    << w.halfSide[1] << w.length << w.radiusStart << w.radiusEnd << w.angularVelocity << w.pivot;
  // Only a wall with its own friction adds it: the others keep their fingerprints.
  if (w.friction) c << std::string("friction") << *w.friction;
  // A mesh's triangles as read (scaled, turned, moved), not its file's path: the same mesh
  // written another way is the same run.
  if (w.mesh) {
    c << std::uint64_t(w.mesh->body->vertex.size());
    for (const Vec3& v : w.mesh->body->vertex) c << v;
    for (const auto& t : w.mesh->body->triangle) {
      for (std::uint32_t k : t) c << std::uint64_t(k);
    }
  }
  return c.hash();
}

std::uint64_t gridHash(const GridGenerator& g) {
  const auto& [origin, cellSize, cells, count, radiusMin, radiusMax, speedMax, seed] = g;
  Canonical c;
  c << std::string("grid") << origin << cellSize << cells[0] << cells[1] << cells[2]
    << std::uint64_t(count) << radiusMin << radiusMax << speedMax << seed;
  return c.hash();
}

/// The particles' values, not the file's path or bytes: the same particles moved elsewhere or
/// written another way are the same run (ParticleCsv::contentHash).
std::uint64_t csvHash(const CsvGenerator& g) {
  const auto& [path, contentHash, savedState] = g;
  Canonical c;
  // A saved state is another source than a particle file of the same rows (its masses, its
  // overlaps); a particle file's part is as it was before saved states were read.
  const std::string kind = savedState ? "state" : "csv";
  if (contentHash) {
    c << kind << *contentHash;
    return c.hash();
  }
  try {
    c << kind
      << readParticleCsv(path, savedState ? CsvKind::SavedState : CsvKind::Particles).contentHash;
  } catch (const ConfigError& e) {
    throw CheckpointError(e.what());
  }
  return c.hash();
}

void hashRegion(Canonical& c, const Region& r) {
  const auto& [shape, min, max, base, axis, length, radius] = r;
  c << shape << min << max << base << axis << length << radius;
}

std::uint64_t stageHash(const StageSpec& s) {
  const auto& [name, end, wallMotions, removeWalls, inserts, outlets, exchangeInterval,
               placeTopWallOnSurface, resetClock, snapshotTimes] = s;
  const auto& [maxTime, kineticEnergyBelow, sustainTime] = end;
  Canonical c;
  c << name << maxTime << kineticEnergyBelow << sustainTime << placeTopWallOnSurface << resetClock
    << std::uint64_t(wallMotions.size());
  for (const WallMotion& motion : wallMotions) {
    const auto& [wall, velocity] = motion;
    c << wall << velocity;
  }
  // The output a resumed run continues, as [output]'s; only a stage that lists its own adds
  // them, so the others keep their fingerprints.
  if (snapshotTimes) {
    c << std::string("snapshots") << std::uint64_t(snapshotTimes->size());
    for (double t : *snapshotTimes) c << t;
  }
  // Only a stage that exchanges particles or opens a gate adds them: the others keep their
  // fingerprints.
  if (!removeWalls.empty() || !inserts.empty() || !outlets.empty()) {
    c << std::string("exchange") << exchangeInterval << std::uint64_t(removeWalls.size());
    for (const std::string& wall : removeWalls) c << wall;
    c << std::uint64_t(inserts.size());
    for (const InsertSpec& insert : inserts) {
      const auto& [iname, region, count, rate, radiusMin, radiusMax, velocity, seed, source] =
          insert;
      c << iname;
      hashRegion(c, region);
      c << count << rate << radiusMin << radiusMax << velocity << seed << std::uint64_t(source);
    }
    c << std::uint64_t(outlets.size());
    for (const OutletSpec& outlet : outlets) {
      const auto& [oname, region] = outlet;
      c << oname;
      hashRegion(c, region);
    }
  }
  return c.hash();
}

std::uint64_t outputHash(const OutputSpec& o) {
  // The run checks only watch the run: a limit relaxed after a stop may resume the same run.
  const auto& [interval, snapshotTimes, checks] = o;
  (void)checks;
  Canonical c;
  c << interval << std::uint64_t(snapshotTimes.size());
  for (double t : snapshotTimes) c << t;
  return c.hash();
}

}  // namespace

SceneFingerprint fingerprintScene(const Scene& scene) {
  const auto& [sourceFile, simulation, box, walls, generators, totalMass, stages, output,
               keyLocations, warnings] = scene;
  // The scene file's name, the keys' lines and the loader's warnings are not part of the run:
  // only what messages say.
  static_cast<void>(keyLocations);
  static_cast<void>(warnings);
  const std::string in = sourceFile.empty() ? " of the scene" : " in " + sourceFile.string();
  const auto& [material, gravity, integrator, timeStep, step, skin, impactSpeed, threads, exactSums,
               smallestRadius] = simulation;
  // The motion is the same bits for any thread count and either way of summing the energies and
  // wall reactions (simulation.exact_sums): a checkpoint written one way resumes the other.
  static_cast<void>(threads);
  static_cast<void>(exactSums);

  SceneFingerprint f;
  f.parts.push_back({"material", materialHash(material), "[material]" + in});
  Canonical sim;
  sim << gravity << integrator << timeStep << skin;
  // An automatic step's settings shape the run; a fixed step's on_unstable does not (it stops
  // or warns, the steps are the same), and fixed scenes keep the fingerprints they had.
  if (step.automatic) {
    sim << std::string("auto") << step.safety << step.contactResolution << step.recheckSteps;
  }
  if (smallestRadius > 0) sim << std::string("smallest radius") << smallestRadius;
  f.parts.push_back({"simulation", sim.hash(), "[simulation]" + in});
  // Apart from [simulation]: when not given, it is computed from the particles, and a message
  // about an edited particle file should not blame [simulation] for it.
  Canonical impact;
  impact << impactSpeed;
  f.parts.push_back({"simulation.impact_speed", impact.hash(),
                     "simulation.impact_speed (given" + in + ", or computed from the particles)"});
  f.parts.push_back({"box", boxHash(box), "[box]" + in});
  // Only a scene with walls beside the box has the part: the others keep their fingerprints.
  for (std::size_t i = 0; i < walls.size(); ++i) {
    const std::string key = "walls[" + std::to_string(i) + "]";
    f.parts.push_back({key, wallHash(walls[i]), key + " '" + walls[i].name + "'" + in});
  }
  for (std::size_t i = 0; i < generators.size(); ++i) {
    const std::string key = "particles[" + std::to_string(i) + "]";
    if (const auto* grid = std::get_if<GridGenerator>(&generators[i])) {
      f.parts.push_back({key, gridHash(*grid), key + " (grid)" + in});
    } else {
      const CsvGenerator& csv = std::get<CsvGenerator>(generators[i]);
      f.parts.push_back(
          {key, csvHash(csv), "the particle file " + csv.path.string() + " (" + key + ".file)"});
    }
  }
  Canonical mass;
  mass << totalMass;
  f.parts.push_back({"total_mass", mass.hash(), "total_mass" + in});
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const std::string key = "stages[" + std::to_string(i) + "]";
    f.parts.push_back({key, stageHash(stages[i]), key + " '" + stages[i].name + "'" + in});
  }
  f.parts.push_back({"output", outputHash(output), "[output]" + in});
  return f;
}

}  // namespace granular
