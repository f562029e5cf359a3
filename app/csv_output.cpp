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

void check(const std::ofstream& out, const std::filesystem::path& path) {
  if (!out) throw IoError(path.string() + ": cannot write");
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
                                   std::vector<std::string> walls)
    : path_(path), out_(path), walls_(std::move(walls)) {
  if (!out_) throw IoError(path.string() + ": cannot create");
  out_ << "stage,time_s,step,kinetic_translational_J,kinetic_rotational_J,elastic_normal_J,"
          "elastic_tangential_J,dissipated_normal_J,dissipated_tangential_J,"
          "dissipated_friction_J,tangential_stiffness_work_J,gravity_work_J,wall_work_J,"
          "energy_total_J,contacts_particle_overlapping,contacts_wall_overlapping";
  for (const std::string& wall : walls_) {
    for (const char* axis : {"x", "y", "z"}) {
      out_ << ",reaction_" << wall << '_' << axis << "_N";  // wall names need no quoting
    }
  }
  out_ << "\n" << std::flush;
  check(out_, path_);
  bytes_ = std::uint64_t(out_.tellp());
}

TimeSeriesWriter::TimeSeriesWriter(const std::filesystem::path& path,
                                   std::vector<std::string> walls, std::uint64_t bytes)
    : path_(path), walls_(std::move(walls)) {
  std::error_code ec;
  const std::uintmax_t size = std::filesystem::file_size(path, ec);
  if (ec || size < bytes) {
    throw IoError(path.string() + ": cannot resume the time series: it has " +
                  (ec ? std::string("gone") : std::to_string(size) + " bytes") +
                  ", the checkpoint " + "expects at least " + std::to_string(bytes));
  }
  std::filesystem::resize_file(path, bytes, ec);
  if (ec) throw IoError(path.string() + ": cannot truncate: " + ec.message());
  out_.open(path, std::ios::app | std::ios::binary);
  check(out_, path_);
  bytes_ = bytes;
}

void TimeSeriesWriter::write(const std::string& stage, const Simulation& sim) {
  const EnergyBalance e = sim.energy();
  const StepCounters& c = sim.counters();
  std::ostringstream row;
  row << csvField(stage) << ',' << csvNumber(sim.time()) << ',' << sim.stepCount();
  for (double value :
       {e.kineticTranslational, e.kineticRotational, e.elasticNormal, e.elasticTangential,
        e.dissipatedNormal, e.dissipatedTangential, e.dissipatedFriction, e.tangentialStiffnessWork,
        e.gravityWork, e.wallWork, e.total()}) {
    row << ',' << csvNumber(value);
  }
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
  row << '\n';
  const std::string text = row.str();
  out_ << text << std::flush;
  bytes_ += text.size();
  check(out_, path_);
}

void writeTextFile(const std::filesystem::path& path, const std::string& text) {
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  {
    std::ofstream out(temporary);
    if (!out) throw IoError(temporary.string() + ": cannot create");
    out << text;
    out.flush();
    check(out, temporary);
  }
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) throw IoError(path.string() + ": cannot write: " + error.message());
}

namespace {

/// The particle-state table; `suffix` ends every row (after the mass) and `extraColumns` the
/// header.
std::string particleTable(const Particles& particles, const std::string& extraColumns,
                          const std::string& suffix) {
  std::ostringstream out;
  out << "id,x,y,z,vx,vy,vz,wx,wy,wz,radius,mass" << extraColumns << "\n";
  for (std::size_t i = 0; i < particles.size(); ++i) {
    out << i;
    for (const Vec3* v :
         {&particles.position[i], &particles.velocity[i], &particles.angularVelocity[i]}) {
      out << ',' << csvNumber(v->x()) << ',' << csvNumber(v->y()) << ',' << csvNumber(v->z());
    }
    out << ',' << csvNumber(particles.radius[i]) << ',' << csvNumber(particles.mass[i]) << suffix
        << '\n';
  }
  return out.str();
}

}  // namespace

void writeParticleState(const std::filesystem::path& path, const Particles& particles) {
  writeTextFile(path, particleTable(particles, "", ""));
}

void writeParticleSnapshot(const std::filesystem::path& path, const Simulation& sim) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "," + std::string + ...
  std::string when = ",";
  when += std::to_string(sim.stepCount());
  when += ',';
  when += csvNumber(sim.time());
  writeTextFile(path, particleTable(sim.particles(), ",step,time_s", when));
}

}  // namespace granular::app
