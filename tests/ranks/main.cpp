/// The rank tests' main: GoogleTest on every rank of an MPI run (tests/CMakeLists.txt starts it
/// under mpirun on 1 to 4 ranks). Rank 0 prints; every rank exits non-zero when any rank failed.
#include <gtest/gtest.h>

#include "granular/mpi_session.hpp"
#include "ranks.hpp"

namespace granular::testing {
namespace {
const Communicator* theWorld = nullptr;
}
const Communicator& world() {
  return *theWorld;
}
}  // namespace granular::testing

int main(int argc, char** argv) {
  granular::MpiSession mpi(argc, argv);
  const std::unique_ptr<granular::Communicator> world = mpi.world();
  granular::testing::theWorld = world.get();
  ::testing::InitGoogleTest(&argc, argv);
  if (world->rank() != 0) {
    ::testing::TestEventListeners& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  const bool failed = RUN_ALL_TESTS() != 0;
  const bool anyFailed = world->anyOverRanks(failed);
  if (failed) std::fprintf(stderr, "rank %d of %d: a test failed\n", world->rank(), world->size());
  return anyFailed ? 1 : 0;
}
