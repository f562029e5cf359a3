/// Checkpoint writing and reading (checkpoint.hpp). Sections: byte streams, the state's fields in
/// one order for both directions, the file frame.
#include "granular/checkpoint.hpp"

#include <algorithm>
#include <array>
#include <cstring>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "fnv1a.hpp"
#include "granular/contact_model.hpp"
#include "granular/error.hpp"
#include "granular/output_file.hpp"
#include "granular/wall_mesh.hpp"
#include "number_format.hpp"
#include "pair_springs.hpp"
#include "particle_fields.hpp"
#include "simulation_state.hpp"
#include "state_checks.hpp"

namespace granular {

namespace {

constexpr char kMagic[8] = {'G', 'R', 'A', 'N', 'C', 'K', 'P', 'T'};

// ---- The composite fields -----------------------------------------------------------------

/// A fingerprint part as the file holds it (its label is for messages only).
struct StoredPart {
  std::string key;
  std::uint64_t hash = 0;
};

template <class Io>
void fields(Io& io, StoredPart& p) {
  io(p.key), io(p.hash);
}

/// A material parameter as the file holds it (format 5): by key, so that a parameter this build
/// declares and the file lacks keeps its default, and one the file has and this build lacks is
/// an error that names it.
struct StoredParameter {
  std::string key;
  double value = 0;
};

/// The contact model's terms when format 5 began to store parameters and accounts by key.
bool formatBeganWith(std::string_view term) {
  constexpr std::string_view kTerms[] = {"body",
                                         "normal_elastic",
                                         "normal_damping",
                                         "tangential_spring",
                                         "tangential_damping",
                                         "rolling_resistance"};
  return std::find(std::begin(kTerms), std::end(kTerms), term) != std::end(kTerms);
}

template <class Io>
void fields(Io& io, StoredParameter& p) {
  io(p.key), io(p.value);
}

template <class Io>
void fields(Io& io, Wall& w) {
  io(w.name), io(w.point), io(w.normal), io(w.velocity), io(w.reaction), io(w.impulse);
}
/// An energy account as the file holds it (format 5): its column, its value at the last force
/// evaluation, its sum since the start, and (Stored) its value at the start.
struct StoredAccount {
  std::string column;
  double now = 0, sinceStart = 0, initial = 0;
};

template <class Io>
void fields(Io& io, StoredAccount& a) {
  io(a.column), io(a.now), io(a.sinceStart), io(a.initial);
}

/// One term's run of history slots as a file lays them out (format 5 stores the list; older
/// files hold the tangential spring's four alone).
struct HistoryTerm {
  std::string term;
  std::uint64_t slots = 0;
};

template <class Io>
void fields(Io& io, HistoryTerm& t) {
  io(t.term), io(t.slots);
}

template <class Io>
void fields(Io& io, ContactHistory& h) {
  io.history(h);
}

/// The terms with history slots that act in `material` (an optional term it leaves off holds
/// nothing and is not written), in the order a ContactHistory holds them.
std::vector<HistoryTerm> historyLayout(const Material& material) {
  std::vector<HistoryTerm> layout;
  for (const TermSpec& t : contactTerms()) {
    if (t.history.empty() || (t.active && !t.active(material))) continue;
    layout.push_back({std::string(t.name), t.history.size()});
  }
  return layout;
}

/// Each term of a history layout as (offset in a ContactHistory, slots); a term this build's
/// contact model does not declare with as many slots is refused (`corrupted`).
template <class Refuse>
std::vector<std::pair<std::size_t, std::size_t>> historyRuns(const std::vector<HistoryTerm>& layout,
                                                             Refuse&& corrupted) {
  std::vector<std::pair<std::size_t, std::size_t>> runs;
  for (const HistoryTerm& t : layout) {
    const auto terms = contactTerms();
    const auto it = std::find_if(terms.begin(), terms.end(),
                                 [&](const TermSpec& spec) { return spec.name == t.term; });
    if (it == terms.end() || it->history.size() != t.slots) {
      corrupted("its contacts carry the history of a term '" + printable(t.term) + "' with " +
                std::to_string(t.slots) +
                " slots, which this build's contact model does not declare");
    }
    runs.push_back({it->historyOffset, it->history.size()});
  }
  return runs;
}

// ---- Byte streams: one call operator per direction, the same field order ------------------

class Writer {
 public:
  template <class T>
  void operator()(T& value) {
    if constexpr (std::is_same_v<T, Vec3>) {
      for (int k = 0; k < 3; ++k) raw(value[k]);
    } else if constexpr (std::is_same_v<T, std::string>) {
      std::uint64_t n = value.size();
      raw(n);
      bytes_.insert(bytes_.end(), value.begin(), value.end());
    } else if constexpr (requires { fields(*this, value); }) {
      fields(*this, value);
    } else if constexpr (requires { value.resize(0); }) {
      std::uint64_t n = value.size();
      raw(n);
      for (auto& item : value) (*this)(item);
    } else {
      raw(value);
    }
  }
  const std::vector<char>& bytes() const { return bytes_; }
  /// The history layout written: the slots of these terms, per contact.
  void setHistoryLayout(const std::vector<HistoryTerm>& layout) {
    historyRuns_ = historyRuns(layout, [](const std::string& what) {
      throw std::logic_error("checkpoint writer: " + what);
    });
  }
  /// A contact's history: the slots of the layout's terms.
  void history(ContactHistory& h) {
    for (const auto& [offset, count] : historyRuns_) {
      for (std::size_t k = 0; k < count; ++k) raw(h.slot[offset + k]);
    }
  }
  static constexpr std::uint32_t version() { return kCheckpointVersion; }

 private:
  template <class T>
  void raw(const T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    const char* p = reinterpret_cast<const char*>(&value);
    bytes_.insert(bytes_.end(), p, p + sizeof(T));
  }
  std::vector<char> bytes_;
  std::vector<std::pair<std::size_t, std::size_t>> historyRuns_;  ///< (offset, slots) per term
};

class Reader {
 public:
  Reader(const char* data, std::size_t size, const std::string& file, std::uint32_t version)
      : data_(data), size_(size), file_(file), version_(version) {}
  std::uint32_t version() const { return version_; }
  /// The file's history layout, mapped onto this build's: each of the file's terms must be one
  /// this build declares with as many slots; a term the file lacks keeps zero slots.
  void setHistoryLayout(const std::vector<HistoryTerm>& layout) {
    historyRuns_ = historyRuns(layout, [this](const std::string& what) { corrupted(what); });
  }
  /// The slot of the energy account with this column; a column this build does not declare is
  /// refused by name.
  std::size_t energySlot(std::string_view column) const {
    if (const EnergyAccountSpec* a = findEnergyAccount(column)) return a->slot;
    corrupted("it holds an energy account '" + printable(column) +
              "', which this build's contact model does not declare");
  }
  void history(ContactHistory& h) {
    for (const auto& [offset, count] : historyRuns_) {
      for (std::size_t k = 0; k < count; ++k) raw(h.slot[offset + k]);
    }
  }
  template <class T>
  void operator()(T& value) {
    if constexpr (std::is_same_v<T, Vec3>) {
      for (int k = 0; k < 3; ++k) raw(value[k]);
    } else if constexpr (std::is_same_v<T, bool>) {
      // Only the bytes 0 and 1 are bools: copying any other byte into a bool and reading it is
      // undefined behaviour (found by fuzz/fuzz_checkpoint.cpp).
      static_assert(sizeof(bool) == 1, "the writer stores a bool as one byte");
      unsigned char byte = 0;
      raw(byte);
      if (byte > 1) {
        throw CheckpointError(file_ + ": corrupted checkpoint: a flag is " + std::to_string(byte) +
                              ", not 0 or 1");
      }
      value = byte == 1;
    } else if constexpr (std::is_same_v<T, std::string>) {
      const std::size_t n = count(1);
      value.assign(take(n), n);
    } else if constexpr (requires { fields(*this, value); }) {
      fields(*this, value);
    } else if constexpr (requires { value.resize(0); }) {
      value.resize(count(1));
      for (std::size_t i = 0; i < value.size(); ++i) {
        typename T::value_type item{};
        (*this)(item);
        value[i] = item;
      }
    } else {
      raw(value);
    }
  }
  bool atEnd() const { return pos_ == size_; }
  [[noreturn]] void corrupted(const std::string& what) const {
    throw CheckpointError(file_ + ": corrupted checkpoint: " + what);
  }

 private:
  /// An element count, checked against what is left so a corrupted one cannot ask for terabytes.
  std::size_t count(std::size_t minBytes) {
    std::uint64_t n = 0;
    raw(n);
    if (n > (size_ - pos_) / minBytes) fail();
    return static_cast<std::size_t>(n);
  }
  const char* take(std::size_t n) {
    if (size_ - pos_ < n) fail();
    const char* p = data_ + pos_;
    pos_ += n;
    return p;
  }
  template <class T>
  void raw(T& value) {
    static_assert(std::is_trivially_copyable_v<T>);
    std::memcpy(&value, take(sizeof(T)), sizeof(T));
  }
  [[noreturn]] void fail() const {
    throw CheckpointError(file_ + ": corrupted checkpoint: a field runs past the end of the data");
  }
  const char* data_;
  std::size_t size_;
  std::string file_;
  std::uint32_t version_;
  std::vector<std::pair<std::size_t, std::size_t>> historyRuns_;  ///< (offset, slots) per term
  std::size_t pos_ = 0;
};

/// A wall's shape and turn, after format 7's fields when any wall is not an infinite plane (a
/// scene of planes keeps the bytes it had; a build before shells refuses the section as
/// trailing data).
constexpr std::string_view kWallShapesTag = "wall_shapes";
/// The walls' own friction, when any wall has its own.
constexpr std::string_view kWallFrictionTag = "wall_friction";
/// Particles inserted and removed, walls taken away, and the smallest radius a run that
/// inserts particles was set up for: last, when the run has any of them.
constexpr std::string_view kExchangeTag = "particle_exchange";

bool hasExchange(const SimulationState& s) {
  return s.exchange.any() || s.config.smallestRadius > 0 ||
         std::any_of(s.walls.begin(), s.walls.end(), [](const Wall& w) { return w.removed; });
}

/// The exchange section's fields (kExchangeTag).
template <class Io>
void exchangeFields(Io& io, SimulationState& s) {
  io(s.config.smallestRadius);
  ExchangeTally& x = s.exchange;
  io(x.inserted), io(x.removed), io(x.insertedBy);
  for (ExactSum* sum : {&x.startMass, &x.insertedMass, &x.removedMass, &x.net}) {
    std::vector<std::int64_t> words;
    if constexpr (std::is_same_v<Io, Writer>) {
      const ExactSum::Words w = sum->words();
      words.assign(w.begin(), w.end());
    }
    io(words);
    if constexpr (std::is_same_v<Io, Reader>) {
      ExactSum::Words w{};
      if (words.size() != w.size()) io.corrupted("a mass tally has the wrong length");
      std::copy(words.begin(), words.end(), w.begin());
      *sum = ExactSum::fromWords(w);
    }
  }
  io(s.energy.exchanged);
  std::vector<std::uint8_t> removed;
  if constexpr (std::is_same_v<Io, Writer>) {
    for (const Wall& w : s.walls) removed.push_back(w.removed ? 1 : 0);
  }
  io(removed);
  if constexpr (std::is_same_v<Io, Reader>) {
    if (removed.size() != s.walls.size()) io.corrupted("the removed walls do not match the walls");
    for (std::size_t w = 0; w < removed.size(); ++w) {
      if (removed[w] > 1) io.corrupted("a wall's removed flag is not 0 or 1");
      s.walls[w].removed = removed[w] == 1;
    }
    if (!std::isfinite(s.config.smallestRadius) || s.config.smallestRadius < 0) {
      io.corrupted("the smallest radius is not a length");
    }
  }
}

template <class Io>
void frictionFields(Io& io, Wall& w) {
  std::uint8_t own = w.friction.has_value() ? 1 : 0;
  double value = w.friction.value_or(0.0);
  io(own), io(value);
  if constexpr (std::is_same_v<Io, Reader>) {
    if (own > 1) io.corrupted("a wall's friction flag is neither 0 nor 1");
    if (own == 1) {
      w.friction = value;
    } else {
      w.friction.reset();
    }
  }
}

template <class Io>
void shapeFields(Io& io, Wall& w) {
  io(w.shape), io(w.edge), io(w.halfSide[0]), io(w.halfSide[1]), io(w.length);
  io(w.radiusStart), io(w.radiusEnd), io(w.angularVelocity), io(w.pivot), io(w.travel);
  if (w.shape != WallShape::Mesh) return;
  // A mesh: its triangles in its own frame, posed again on reading.
  std::vector<Vec3> vertex;
  std::vector<std::array<std::uint32_t, 3>> triangle;
  if constexpr (std::is_same_v<Io, Writer>) {
    vertex = w.mesh->body->vertex;
    triangle = w.mesh->body->triangle;
  }
  io(vertex), io(triangle);
  if constexpr (std::is_same_v<Io, Reader>) {
    auto body = std::make_shared<TriangleMesh>();
    body->vertex = std::move(vertex);
    body->triangle = std::move(triangle);
    std::vector<MeshDefect> defects;
    meshTopology(*body, false, defects);
    if (!defects.empty() || body->triangle.empty())
      io.corrupted("a mesh wall's triangles are not sound");
    w.mesh = poseMesh(std::move(body), w.point, w.normal, w.edge);
  }
}

// ---- The state, field by field, in one order for both directions --------------------------

/// A per-particle field's array (particle_fields.hpp). A file older than the field lacks it:
/// the state then holds it at zero, where it holds it at all.
template <class Io, class T>
void fieldIo(Io& io, const SimulationState& s, const FieldSpec& field, std::vector<T>& values) {
  if constexpr (std::is_same_v<Io, Reader>) {
    if (io.version() < field.since) {
      T zero;
      if constexpr (std::is_same_v<T, Vec3>) {
        zero = Vec3::Zero();
      } else {
        zero = T{};
      }
      values.assign(holds(s, field.needs) ? s.particles.size() : 0, zero);
      return;
    }
  }
  io(values);
}

template <class Io>
void fields(Io& io, SimulationState& s) {
  Material& m = s.config.material;
  io(m.youngModulus), io(m.poissonRatio), io(m.shearModulus), io(m.density), io(m.friction);
  io(m.normalDamping), io(m.tangentialDamping), io(m.normalLaw);
  SimulationConfig& c = s.config;
  io(c.gravity), io(c.integrator), io(c.timeStep), io(c.skin), io(c.impactSpeed);
  io(s.timeOrigin), io(s.stepsSinceOrigin), io(s.steps), io(s.frictional);
  io(s.contactScale.duration), io(s.contactScale.radius), io(s.contactScale.againstWall);
  Particles& p = s.particles;
  auto perParticle = [&](const FieldSpec& field, auto& values) { fieldIo(io, s, field, values); };
  forEachParticleField(p, perParticle);
  io(s.walls);
  forEachMotionField(s, perParticle);
  NeighbourList& n = s.neighbours;
  // The file holds a spring per candidate pair (zero for those holding none): the layout in
  // memory (pair_springs.hpp) depends on the particle blocks, derived data built on loading.
  // Likewise the first particle of each pair, which memory holds as rows.
  std::vector<HistoryTerm> layout = historyLayout(s.config.material);
  if constexpr (std::is_same_v<Io, Reader>) {
    if (io.version() < 5) layout = {{std::string(TangentialSpring::name), 4}};
  }
  if (io.version() >= 5) io(layout);
  io.setHistoryLayout(layout);
  std::vector<ContactHistory> history;
  std::vector<std::uint32_t> first;
  if constexpr (std::is_same_v<Io, Writer>) {
    history = perPairSprings(n);
    first = firstOfPairs(n);
  }
  io(first), io(n.second), io(history), io(n.wallParticles), io(n.wallHistory);
  if constexpr (std::is_same_v<Io, Reader>) {
    if (!rowsFromFirst(n, first, p.size())) io.corrupted("the pair list is not sorted");
    // Derived, not in the file: binned and searched again from the walls and positions read.
    n.meshGrid.clear();
    n.meshGridPose.clear();
    n.meshTriangleStart.clear();
    n.meshTriangles.clear();
    std::vector<std::uint32_t>().swap(first);
    buildPairBlocks(n, p.size());
    // Records of every term's slots: the material (read later) is not known yet; the first
    // force pass keeps those of the terms it uses.
    layOutPairSprings(n, history, (1u << kOptionalTerms) - 1);
  }
  // The reference positions as doubles, as files before single precision held them.
  std::vector<Vec3> reference;
  if constexpr (std::is_same_v<Io, Writer>) {
    reference.reserve(n.referencePosition.size());
    for (const Eigen::Vector3f& x : n.referencePosition) reference.push_back(x.cast<double>());
  }
  io(reference), io(n.referenceWallPoint), io(n.skin), io(n.valid);
  if constexpr (std::is_same_v<Io, Reader>) setReferencePositions(n, reference);
  // The paper's model's accounts by column, in the order versions 2 to 4 hold them (format 5
  // adds every account by column at the end of the payload: energyAccountsIo).
  ContactPowers& w = s.powers;
  EnergyAccumulators& e = s.energy;
  double unused = 0;  // an account this model does not declare (written as 0, read and dropped)
  auto slot = [](std::string_view column) -> std::optional<std::size_t> {
    const EnergyAccountSpec* a = findEnergyAccount(column);
    return a ? std::optional<std::size_t>(a->slot) : std::nullopt;
  };
  auto now = [&](std::string_view column) -> double& {
    const auto at = slot(column);
    return at ? w.energy[*at] : (unused = 0);
  };
  auto since = [&](std::string_view column) -> double& {
    const auto at = slot(column);
    return at ? e.account[*at] : (unused = 0);
  };
  io(now("elastic_normal_J")), io(now("elastic_tangential_J")), io(now("dissipated_normal_J"));
  io(now("dissipated_tangential_J")), io(now("tangential_work_J"));
  io(now("tangential_stiffness_work_J")), io(w.wallPower);
  io(w.particleContacts), io(w.wallContacts), io(w.tangentialEvaluations);
  io(since("dissipated_normal_J")), io(since("dissipated_tangential_J"));
  io(since("tangential_work_J")), io(since("tangential_stiffness_work_J"));
  io(e.wallWork), io(e.initialPotential);
  const auto tangential = slot("elastic_tangential_J");
  io(tangential ? e.initialStored[*tangential] : (unused = 0));
  StepCounters& k = s.counters;
  io(k.particleContacts), io(k.wallContacts), io(k.neighbourPairs), io(k.rebuilds);
  io(k.tangentialEvaluations);
}

// ---- The file frame -----------------------------------------------------------------------

struct Header {
  char magic[8];
  std::uint32_t version;
  std::uint64_t fingerprint;
  std::uint64_t payloadBytes;
};

/// The frame before the payload: magic, version, fingerprint, payload length.
constexpr std::size_t kFrameBytes =
    sizeof kMagic + sizeof(std::uint32_t) + 2 * sizeof(std::uint64_t);

/// The whole file, read only once its size is what its header announces, so that a corrupted
/// length or a file that is not a checkpoint (a folder, /dev/zero, a huge file) never makes it
/// allocate more than the checkpoint it claims to be.
std::string readAll(const std::filesystem::path& file) {
  InputFile in(file, "checkpoint");
  const std::uint64_t size = in.size();
  if (size >= kFrameBytes + sizeof(std::uint64_t)) {
    std::uint64_t payloadBytes = 0;
    const std::string field = in.read(kFrameBytes - sizeof payloadBytes, sizeof payloadBytes);
    std::memcpy(&payloadBytes, field.data(), sizeof payloadBytes);
    if (size - kFrameBytes - sizeof(std::uint64_t) != payloadBytes) {
      throw CheckpointError(
          file.string() + ": truncated or padded checkpoint: " + std::to_string(size) +
          " bytes, the header announces a " + std::to_string(payloadBytes) + "-byte payload in a " +
          std::to_string(kFrameBytes + sizeof(std::uint64_t)) + "-byte frame");
    }
  }
  const std::uint64_t available = availableMemoryBytes();
  if (available > 0 && size > available) {
    throw IoError(file.string() + ": cannot read checkpoint: " + std::to_string(size) +
                  " bytes, more than the " + std::to_string(available) +
                  " bytes of memory available");
  }
  return in.readAll(size);
}

template <class T>
void put(std::vector<char>& out, const T& v) {
  const char* p = reinterpret_cast<const char*>(&v);
  out.insert(out.end(), p, p + sizeof(T));
}

}  // namespace

namespace {

/// The frame around the payload: header, parts, state, caller's data, checksum.
void writeFrame(const Simulation& sim, const std::filesystem::path& file,
                std::uint64_t headerFingerprint, std::vector<StoredPart> parts,
                const std::string& appData) {
  const SimulationState& state = SimulationAccess::state(sim);
  if (const std::optional<std::string> bad = firstNonFiniteParticle(state.particles)) {
    throw CheckpointError(file.string() + ": not writing a checkpoint of a broken state: " + *bad);
  }
  Writer w;
  w(parts);
  fields(w, const_cast<SimulationState&>(state));  // read only
  std::string data = appData;
  w(data);
  bool noPull = state.config.material.noPull;  // version 4
  w(noPull);
  // Version 5: the material's parameters and the energy accounts by key. Those of the terms
  // the format began with always; a later term's only where they hold something (a parameter
  // off its default, an account not zero), so that a term added with its default (off) leaves
  // every run's checkpoint as it was. A reader takes what the file lacks as the default (zero).
  std::vector<StoredParameter> material;
  for (const ParameterSpec& p : materialParameters()) {
    const double value = p.get(state.config.material);
    if (formatBeganWith(p.term) || std::memcmp(&value, &p.defaultValue, sizeof value) != 0) {
      material.push_back({std::string(p.key), value});
    }
  }
  w(material);
  std::vector<StoredAccount> accounts;
  for (const EnergyAccountSpec& a : energyAccounts()) {
    const StoredAccount account{std::string(a.account.column), state.powers.energy[a.slot],
                                state.energy.account[a.slot], state.energy.initialStored[a.slot]};
    if (formatBeganWith(a.term) || account.now != 0.0 || account.sinceStart != 0.0 ||
        account.initial != 0.0) {
      accounts.push_back(account);
    }
  }
  w(accounts);
  StepControl step = state.config.step;  // version 6
  double targetStep = state.targetStep;
  std::uint64_t sinceCheck = state.stepsSinceCheck;
  w(step.automatic), w(step.safety), w(step.contactResolution), w(step.recheckSteps);
  w(step.onUnstable), w(targetStep), w(sinceCheck);
  StepCounters counters = state.counters;  // version 7
  StepCheck check = state.stepCheck;
  w(counters.stepChecks), w(counters.unstableChecks), w(counters.worstStepRatio);
  w(counters.smallestStep), w(counters.largestStep);
  w(check.time), w(check.networkStep), w(check.omegaMax), w(check.dampingRatio);
  w(check.particle), w(check.contacts), w(check.accuracyStep), w(check.chosenStep);
  NetworkCalibration calibration = state.calibration;  // version 8
  w(check.estimated), w(calibration.boundOmega), w(calibration.boundDamping);
  w(calibration.omega), w(calibration.damping);
  w(counters.rollbacks), w(counters.keptGrowths), w(calibration.rollbacks);  // version 9
  std::uint64_t checkGap = state.checkGap;                                   // version 10
  w(checkGap);
  if (std::any_of(state.walls.begin(), state.walls.end(),
                  [](const Wall& x) { return x.shell(); })) {
    std::string tag(kWallShapesTag);
    w(tag);
    for (const Wall& wall : state.walls) shapeFields(w, const_cast<Wall&>(wall));  // read only
    std::vector<double> travel = state.neighbours.referenceWallTravel;
    w(travel);
    std::vector<std::vector<Vec3>> normals = state.neighbours.wallNormal;
    w(normals);
  }
  if (std::any_of(state.walls.begin(), state.walls.end(),
                  [](const Wall& x) { return x.friction.has_value(); })) {
    std::string tag(kWallFrictionTag);
    w(tag);
    for (const Wall& wall : state.walls) frictionFields(w, const_cast<Wall&>(wall));  // read only
  }
  if (hasExchange(state)) {
    std::string tag(kExchangeTag);
    w(tag);
    exchangeFields(w, const_cast<SimulationState&>(state));  // read only
  }
  const std::vector<char>& payload = w.bytes();
  std::vector<char> out(kMagic, kMagic + sizeof kMagic);
  put(out, kCheckpointVersion);
  put(out, headerFingerprint);
  put(out, static_cast<std::uint64_t>(payload.size()));
  out.insert(out.end(), payload.begin(), payload.end());
  put(out, fnv1a(payload.data(), payload.size()));

  // On the disk before the rename, and the rename with the folder's entry: after a power cut
  // the old or the new checkpoint is whole.
  writeFileAtomically(file, std::string_view(out.data(), out.size()), /*durable=*/true);
}

/// Each part of `expected` that the checkpoint's parts lack or hold with another hash, and each
/// part the checkpoint has that `expected` lacks, in words; empty when they are the same.
std::string differences(const std::vector<StoredPart>& stored, const SceneFingerprint& expected) {
  std::string out;
  auto add = [&out](const std::string& what) { out += (out.empty() ? "" : "; ") + what; };
  for (const FingerprintPart& part : expected.parts) {
    const auto it = std::find_if(stored.begin(), stored.end(),
                                 [&](const StoredPart& s) { return s.key == part.key; });
    if (it == stored.end()) {
      add(part.label + " is new");
    } else if (it->hash != part.hash) {
      add(part.label + " changed");
    }
  }
  for (const StoredPart& s : stored) {
    const auto it = std::find_if(expected.parts.begin(), expected.parts.end(),
                                 [&](const FingerprintPart& part) { return part.key == s.key; });
    if (it == expected.parts.end()) add("the scene no longer has " + s.key);
  }
  return out;
}

/// What a reader insists on: nothing, a header number, or a scene's parts.
struct Expectation {
  std::uint64_t header = 0;  ///< 0: any
  const SceneFingerprint* scene = nullptr;
};

CheckpointContents parseFrame(std::span<const char> bytes, const std::string& name,
                              const Expectation& expected) {
  const std::size_t frame = kFrameBytes;
  if (bytes.size() < frame + sizeof(std::uint64_t) ||
      std::memcmp(bytes.data(), kMagic, sizeof kMagic) != 0) {
    throw CheckpointError(name + ": not a granular checkpoint (bad magic or too short)");
  }
  std::uint32_t version = 0;
  std::uint64_t fingerprint = 0, payloadBytes = 0, checksum = 0;
  std::size_t pos = sizeof kMagic;
  std::memcpy(&version, bytes.data() + pos, sizeof version);
  pos += sizeof version;
  std::memcpy(&fingerprint, bytes.data() + pos, sizeof fingerprint);
  pos += sizeof fingerprint;
  std::memcpy(&payloadBytes, bytes.data() + pos, sizeof payloadBytes);
  pos += sizeof payloadBytes;
  if (version < 2 || version > kCheckpointVersion) {
    throw CheckpointError(name + ": checkpoint format version " + std::to_string(version) +
                          ", this build reads versions 2 to " + std::to_string(kCheckpointVersion));
  }
  // Compared without adding to payloadBytes, which a corrupted header can make overflow.
  if (bytes.size() - frame - sizeof checksum != payloadBytes) {
    throw CheckpointError(
        name + ": truncated or padded checkpoint: " + std::to_string(bytes.size()) +
        " bytes, the header announces a " + std::to_string(payloadBytes) + "-byte payload in a " +
        std::to_string(frame + sizeof checksum) + "-byte frame");
  }
  std::memcpy(&checksum, bytes.data() + pos + payloadBytes, sizeof checksum);
  if (checksum != fnv1a(bytes.data() + pos, payloadBytes)) {
    throw CheckpointError(name + ": corrupted checkpoint: checksum mismatch");
  }
  Reader r(bytes.data() + pos, payloadBytes, name, version);
  std::vector<StoredPart> parts;
  if (version >= 4) r(parts);
  if (expected.header != 0 && fingerprint != expected.header) {
    throw CheckpointError(name + ": checkpoint belongs to another scene (fingerprint mismatch)");
  }
  if (expected.scene && version < 4) {
    throw CheckpointError(name + ": checkpoint format version " + std::to_string(version) +
                          " identifies its scene by the scene file's bytes alone, not by its "
                          "values and particle files, so it cannot be checked against this scene");
  }
  if (expected.scene) {
    const std::string changed = differences(parts, *expected.scene);
    if (!changed.empty()) {
      throw CheckpointError(name +
                            ": the scene changed since this checkpoint was written: " + changed);
    }
  }
  auto state = std::make_unique<SimulationState>();
  fields(r, *state);
  std::string appData;
  if (version >= 3) r(appData);
  if (version >= 4) r(state->config.material.noPull);
  if (version >= 5) {
    std::vector<StoredParameter> material;
    r(material);
    for (const StoredParameter& p : material) {
      const ParameterSpec* spec = findParameter(p.key);
      if (!spec) {
        throw CheckpointError(name + ": the checkpoint's material has the parameter '" +
                              printable(p.key) +
                              "', which this build's contact model does not declare (written by "
                              "a build with another contact term?)");
      }
      if (!spec->accepts(p.value)) {
        throw CheckpointError(name + ": corrupted checkpoint: material." + std::string(spec->key) +
                              " = " + spec->valueText(p.value) + ": " + spec->requirement());
      }
      spec->set(state->config.material, p.value);
    }
    std::vector<StoredAccount> accounts;
    r(accounts);
    for (const StoredAccount& a : accounts) {
      const std::size_t slot = r.energySlot(a.column);
      state->powers.energy[slot] = a.now;
      state->energy.account[slot] = a.sinceStart;
      state->energy.initialStored[slot] = a.initial;
    }
  }
  if (version >= 6) {
    StepControl& step = state->config.step;
    r(step.automatic), r(step.safety), r(step.contactResolution), r(step.recheckSteps);
    r(step.onUnstable), r(state->targetStep), r(state->stepsSinceCheck);
    const bool sane = std::isfinite(step.safety) && step.safety > 0 && step.safety <= 1 &&
                      std::isfinite(step.contactResolution) && step.contactResolution >= 1 &&
                      step.recheckSteps >= 1 && std::isfinite(state->targetStep) &&
                      state->targetStep >= 0 &&
                      (step.onUnstable == OnUnstable::Stop || step.onUnstable == OnUnstable::Warn);
    if (!sane) throw CheckpointError(name + ": corrupted checkpoint: the step control is invalid");
  }
  if (version >= 7) {
    StepCounters& k = state->counters;
    StepCheck& c = state->stepCheck;
    r(k.stepChecks), r(k.unstableChecks), r(k.worstStepRatio), r(k.smallestStep);
    r(k.largestStep);
    r(c.time), r(c.networkStep), r(c.omegaMax), r(c.dampingRatio), r(c.particle), r(c.contacts);
    r(c.accuracyStep), r(c.chosenStep);
  }
  if (version >= 8) {
    NetworkCalibration& c = state->calibration;
    r(state->stepCheck.estimated), r(c.boundOmega), r(c.boundDamping), r(c.omega), r(c.damping);
    const bool sane = std::isfinite(c.boundOmega) && std::isfinite(c.boundDamping) &&
                      std::isfinite(c.omega) && std::isfinite(c.damping) && c.boundOmega >= 0 &&
                      c.boundDamping >= 0 && c.omega >= 0 && c.damping >= 0;
    if (!sane) {
      throw CheckpointError(name + ": corrupted checkpoint: the spectrum's calibration is invalid");
    }
  }
  if (version >= 9) {
    r(state->counters.rollbacks), r(state->counters.keptGrowths);
    r(state->calibration.rollbacks);
  }
  if (version >= 10) r(state->checkGap);  // any value: recheckSteps bounds the run all the same
  NeighbourList& list = state->neighbours;
  // The optional trailing sections, each tagged, in the order written.
  std::string tag;
  if (version >= 7 && !r.atEnd()) r(tag);
  if (tag == kWallShapesTag) {
    for (Wall& wall : state->walls) {
      shapeFields(r, wall);
      if (wall.shape > WallShape::Mesh) r.corrupted("a wall's shape is unknown");
    }
    r(list.referenceWallTravel);
    r(list.wallNormal);
    tag.clear();
    if (!r.atEnd()) r(tag);
  } else {
    // Infinite planes only: their travel is not used, and is zero where a run keeps it.
    list.referenceWallTravel.assign(list.referenceWallPoint.size(), 0.0);
  }
  if (tag == kWallFrictionTag) {
    for (Wall& wall : state->walls) frictionFields(r, wall);
    tag.clear();
    if (!r.atEnd()) r(tag);
  }
  if (tag == kExchangeTag) {
    exchangeFields(r, *state);
    tag.clear();
  } else {
    // No exchange: the particles held are those the run started with.
    for (double m : state->particles.mass) {
      state->exchange.startMass.add(m);
      state->exchange.net.add(m);
    }
  }
  if (!tag.empty()) r.corrupted("trailing data");
  if (!r.atEnd()) throw CheckpointError(name + ": corrupted checkpoint: trailing data");
  validateRestoredState(*state, name);
  state->neighbours.plan.valid = false;  // derived data: built by the next force pass
  return {SimulationAccess::make(std::move(state)), std::move(appData)};
}

std::vector<StoredPart> storedParts(const SceneFingerprint& fingerprint) {
  std::vector<StoredPart> parts;
  for (const FingerprintPart& part : fingerprint.parts) parts.push_back({part.key, part.hash});
  return parts;
}

}  // namespace

std::uint64_t SceneFingerprint::combined() const {
  Writer w;
  std::vector<StoredPart> stored = storedParts(*this);
  w(stored);
  return fnv1a(w.bytes().data(), w.bytes().size());
}

void writeCheckpoint(const Simulation& sim, const std::filesystem::path& file,
                     const SceneFingerprint& sceneFingerprint, const std::string& appData) {
  writeFrame(sim, file, sceneFingerprint.combined(), storedParts(sceneFingerprint), appData);
}

void writeCheckpoint(const Simulation& sim, const std::filesystem::path& file,
                     std::uint64_t sceneFingerprint, const std::string& appData) {
  writeFrame(sim, file, sceneFingerprint, {}, appData);
}

CheckpointContents parseCheckpoint(std::span<const char> bytes, const std::string& name,
                                   std::uint64_t expectedFingerprint) {
  return parseFrame(bytes, name, {expectedFingerprint, nullptr});
}

CheckpointContents parseCheckpoint(std::span<const char> bytes, const std::string& name,
                                   const SceneFingerprint& expected) {
  return parseFrame(bytes, name, {0, &expected});
}

CheckpointContents readCheckpointWithData(const std::filesystem::path& file,
                                          std::uint64_t expectedFingerprint) {
  const std::string bytes = readAll(file);
  return parseCheckpoint(bytes, file.string(), expectedFingerprint);
}

Simulation readCheckpoint(const std::filesystem::path& file, std::uint64_t expectedFingerprint) {
  return std::move(readCheckpointWithData(file, expectedFingerprint).simulation);
}

CheckpointContents readCheckpointWithData(const std::filesystem::path& file,
                                          const SceneFingerprint& expected) {
  const std::string bytes = readAll(file);
  return parseCheckpoint(bytes, file.string(), expected);
}

Simulation readCheckpoint(const std::filesystem::path& file, const SceneFingerprint& expected) {
  return std::move(readCheckpointWithData(file, expected).simulation);
}

std::uint64_t fingerprintFile(const std::filesystem::path& file) {
  InputFile in(file, "file");
  const std::string bytes = in.readAll(in.size());
  return fnv1a(bytes.data(), bytes.size());
}

}  // namespace granular
