/// force_sums.hpp.
#include "force_sums.hpp"

#include <cmath>
#include <string>
#include <unordered_map>

#include "granular/error.hpp"
#include "granular/vec3.hpp"

namespace granular::app {

std::vector<double> forceSums(const CsvTable& contacts, const std::vector<double>& ids) {
  std::unordered_map<double, std::size_t> row;
  for (std::size_t i = 0; i < ids.size(); ++i) row.emplace(ids[i], i);
  const auto &particle = contacts.column("particle"), &other = contacts.column("other_particle");
  const char* parts[2][3] = {
      {"normal_force_x_N", "normal_force_y_N", "normal_force_z_N"},
      {"tangential_force_x_N", "tangential_force_y_N", "tangential_force_z_N"}};
  const std::vector<double>* component[2][3];
  for (int p = 0; p < 2; ++p) {
    for (int k = 0; k < 3; ++k) component[p][k] = &contacts.column(parts[p][k]);
  }
  std::vector<double> sums(ids.size(), 0.0);
  auto add = [&](double id, std::size_t r, double force) {
    const auto found = row.find(id);
    if (found == row.end()) {
      throw IoError(contacts.file.string() + ":" + std::to_string(contacts.lines[r]) +
                    ": particle " + (std::isfinite(id) ? std::to_string(std::llround(id)) : "?") +
                    " is not in the snapshot beside it");
    }
    sums[found->second] += force;
  };
  for (std::size_t r = 0; r < contacts.rows(); ++r) {
    Vec3 f = Vec3::Zero();
    for (int p = 0; p < 2; ++p) {
      f += Vec3((*component[p][0])[r], (*component[p][1])[r], (*component[p][2])[r]);
    }
    if (!std::isfinite(f.norm())) {
      throw IoError(contacts.file.string() + ":" + std::to_string(contacts.lines[r]) +
                    ": a force that is not a number");
    }
    add(particle[r], r, f.norm());
    // other_particle is empty, read as NaN, for a wall's contact.
    if (!std::isnan(other[r])) add(other[r], r, f.norm());
  }
  return sums;
}

}  // namespace granular::app
