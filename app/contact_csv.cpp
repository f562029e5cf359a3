/// Per-contact CSV (see contact_csv.hpp).
#include "contact_csv.hpp"

#include <sstream>

#include "csv_output.hpp"

namespace granular::app {

void writeContactCsv(const std::filesystem::path& path, const Simulation& sim) {
  std::ostringstream out;
  out << "particle,other_particle,wall,point_x_m,point_y_m,point_z_m,overlap_m,normal_x,normal_y,"
         "normal_z,normal_force_N,normal_force_x_N,normal_force_y_N,normal_force_z_N,"
         "tangential_force_N,tangential_force_x_N,tangential_force_y_N,tangential_force_z_N,"
         "step,time_s\n";
  const std::string when = std::to_string(sim.stepCount()) + ',' + csvNumber(sim.time()) + '\n';
  // x + 0 is x, except that -0 becomes 0: a wall's normal (0, 0, -1) and a clamped contact's
  // zero force read as plain zeros.
  auto number = [](double x) { return csvNumber(x + 0.0); };
  auto vector = [&](const Vec3& v) {
    out << ',' << number(v.x()) << ',' << number(v.y()) << ',' << number(v.z());
  };
  sim.forEachContact([&](const ContactView& c) {
    if (!c.isWall() && c.otherParticle() < c.particle) return;  // a pair once
    out << c.particle << ',';
    if (c.isWall()) {
      out << ',' << sim.walls()[c.wall()].name;  // names need no quoting
    } else {
      out << c.otherParticle() << ',';
    }
    vector(c.point);
    out << ',' << number(c.overlap);
    vector(c.normal);
    const double along = c.force.dot(c.normal);  // < 0: a push away from the other body
    const Vec3 normalForce = along * c.normal;
    const Vec3 tangentialForce = c.force - normalForce;
    out << ',' << number(-along);
    vector(normalForce);
    out << ',' << number(tangentialForce.norm());
    vector(tangentialForce);
    out << ',' << when;
  });
  writeTextFile(path, out.str());
}

}  // namespace granular::app
