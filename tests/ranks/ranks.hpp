#pragma once
/// What the rank tests share: the world of the MPI run they are part of.
#include "granular/communicator.hpp"

namespace granular::testing {
const Communicator& world();
}  // namespace granular::testing
