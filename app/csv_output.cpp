/// CSV output of `granular run` (see csv_output.hpp).
#include "csv_output.hpp"

#include <charconv>
#include <cmath>
#include <sstream>
#include <utility>

namespace granular::app {

namespace {

/// Quotes a field holding a comma, quote or line break (RFC 4180).
std::string csvField(const std::string& text) {
  if (text.find_first_of(",\"\n\r") == std::string::npos) return text;
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + '"';
}

}  // namespace

std::string csvNumber(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x > 0 ? "inf" : "-inf";
  char buffer[64];
  const auto result = std::to_chars(buffer, buffer + sizeof buffer, x);
  return std::string(buffer, result.ptr);
}

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& path,
                                   std::vector<std::string> walls, const Material& material,
                                   bool exchange)
    : file_(path), walls_(std::move(walls)), exchange_(exchange) {
  std::ostringstream header;
  header << "stage,time_s,step,dt_s,kinetic_translational_J,kinetic_rotational_J";
  for (const EnergyAccountSpec& column : energyColumns(material))
    header << ',' << column.account.column;
  header << ",gravity_work_J,wall_work_J,energy_total_J,contacts_particle_overlapping,"
            "contacts_wall_overlapping";
  for (const std::string& wall : walls_) {
    for (const char* axis : {"x", "y", "z"}) {
      header << ",reaction_" << wall << '_' << axis << "_N";  // wall names need no quoting
    }
  }
  if (exchange_) {
    header << ",particles,mass_held_kg,mass_inserted_kg,mass_discharged_kg,mass_balance_kg,"
              "energy_exchanged_J";
  }
  header << "\n";
  file_.append(header.str());
}

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& path,
                                   std::vector<std::string> walls, std::uint64_t bytes,
                                   std::optional<std::uint64_t> hash, bool exchange)
    : file_(path, bytes, hash), walls_(std::move(walls)), exchange_(exchange) {}

void TimeSeriesWriter::write(const std::string& stage, const Simulation& sim) {
  const EnergyBalance e = sim.energy();
  const StepCounters& c = sim.counters();
  std::ostringstream row;
  // dt_s: the step the run takes from here (fixed, or chosen from the contact network).
  row << csvField(stage) << ',' << csvNumber(sim.time()) << ',' << sim.stepCount() << ','
      << csvNumber(sim.config().timeStep);
  row << ',' << csvNumber(e.kineticTranslational) << ',' << csvNumber(e.kineticRotational);
  for (const EnergyAccount& account : e.contact) row << ',' << csvNumber(account.value);
  for (double value : {e.gravityWork, e.wallWork, e.total()}) row << ',' << csvNumber(value);
  row << ',' << c.particleContacts << ',' << c.wallContacts;
  for (const std::string& wall : walls_) {
    const long index = sim.findWall(wall);
    if (index < 0) {
      row << ",,,";
      continue;
    }
    const Vec3& r = sim.walls()[std::size_t(index)].reaction;
    row << ',' << csvNumber(r.x()) << ',' << csvNumber(r.y()) << ',' << csvNumber(r.z());
  }
  if (exchange_) {
    const ParticleTally t = sim.particleTally();
    row << ',' << t.held << ',' << csvNumber(t.heldMass) << ',' << csvNumber(t.insertedMass) << ','
        << csvNumber(t.removedMass) << ',' << csvNumber(t.massBalance) << ','
        << csvNumber(e.exchanged);
  }
  row << '\n';
  file_.append(row.str());
}

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
  writeFileAtomically(path, text);
}

namespace {

/// The particle-state table into `out`; `suffix` ends every row (after the mass) and
/// `extraColumns` the header.
void particleTable(std::ostream& out, const Particles& particles, const std::string& extraColumns,
                   const std::string& suffix, const std::vector<std::uint64_t>* ids = nullptr) {
  out << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius,mass" << extraColumns << "\n";
  for (std::size_t i = 0; i < particles.size(); ++i) {
    out << (ids ? (*ids)[i] : i);
    for (const Vec3* v :
         {&particles.position[i], &particles.velocity[i], &particles.angularVelocity[i]}) {
      out << ',' << csvNumber(v->x()) << ',' << csvNumber(v->y()) << ',' << csvNumber(v->z());
    }
    out << ',' << csvNumber(particles.radius[i]) << ',' << csvNumber(particles.mass[i]) << suffix
        << '\n';
  }
}

}  // namespace

void writeParticleState(const std::filesystem::path& path, const Particles& particles,
                        const std::vector<std::uint64_t>* ids) {
  AtomicFile file(path);
  particleTable(file.stream(), particles, "", "", ids);
  file.commit();
}

void writeParticleSnapshot(const std::filesystem::path& path, const Simulation& sim) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "," + std::string + ...
  std::string when = ",";
  when += std::to_string(sim.stepCount());
  when += ',';
  when += csvNumber(sim.time());
  AtomicFile file(path);
  particleTable(file.stream(), sim.particles(), ",step,time_s", when);
  file.commit();
}

}  // namespace granular::app
