/// σ_zz over horizontal slices of a cylinder (slice_stress.hpp).
#include "granular/slice_stress.hpp"

#include <algorithm>
#include <numbers>
#include <string>

#include "input_checks.hpp"

namespace granular {

SliceStressProfile cylinderSliceStress(const std::vector<SliceContact>& contacts, double radius,
                                       const std::vector<double>& edges) {
  const std::string who = "cylinderSliceStress";
  input_checks::requirePositive(radius, who + ": radius");
  input_checks::requireAscendingEdges(edges, who + ": edge");
  const double section = std::numbers::pi * radius * radius;
  SliceStressProfile profile;
  profile.slices.resize(edges.size() - 1);
  std::vector<double> moment(profile.slices.size(), 0.0);
  for (std::size_t c = 0; c < contacts.size(); ++c) {
    const SliceContact& record = contacts[c];
    const std::string which = who + ": contact[" + std::to_string(c) + "] ";
    input_checks::requireFinite(record.particleHeight, which + "particle height");
    input_checks::requireFinite(record.forceZ, which + "F_z");
    input_checks::requireFinite(record.branchZ, which + "l_z");
    const double z = record.particleHeight;
    if (z < edges.front() || z > edges.back()) {
      ++profile.contactsOutside;
      continue;
    }
    const std::size_t k = z == edges.back()
                              ? moment.size() - 1
                              : std::upper_bound(edges.begin(), edges.end(), z) - edges.begin() - 1;
    moment[k] += record.forceZ * record.branchZ;
    ++profile.slices[k].contacts;
  }
  for (std::size_t k = 0; k < moment.size(); ++k) {
    SliceStress& s = profile.slices[k];
    s.zLow = edges[k];
    s.zHigh = edges[k + 1];
    s.volume = section * (s.zHigh - s.zLow);
    s.sigmaZZ = moment[k] / s.volume;
    s.sigmaV = -s.sigmaZZ;
  }
  return profile;
}

}  // namespace granular
