#pragma once
/// Σ|F_ij| per particle from a snapshot's contacts_<stage>_<step>.csv (contact_csv.hpp): the
/// value the particle figures are coloured by, the same as the ParaView files' force_sum_N.
#include <vector>

#include "csv_input.hpp"

namespace granular::app {

/// For each particle of the snapshot, in the order of `ids` (the snapshot's id column): the sum
/// of |F| over its contacts [N], F the contact's normal plus tangential force. A pair's row
/// counts for both of its particles, a wall's for its particle. IoError naming the contacts file
/// and line when a row names a particle that `ids` does not hold.
std::vector<double> forceSums(const CsvTable& contacts, const std::vector<double>& ids);

}  // namespace granular::app
