/// granular: the command line. Subcommands:
///   granular run SCENE.toml [--out DIR] [--quiet] [--checkpoint-every S] [--resume] [--figures]
///   granular paper [--out DIR] [--scenes DIR] [--fresh] [--quiet]
///   granular figures RUN_DIR
///   granular calibrate-box SCENE.toml --sides A,B,C [--target-height H] [--report FILE]
/// The options live in command_line.cpp; docs/guide.md §8 lists them (a test keeps it true).
#include <malloc.h>

#include <memory>
#include <optional>

#include "command_line.hpp"
#include "granular/mpi_session.hpp"

int main(int argc, char** argv) {
  // Arrays of 1 MiB and more get pages of their own, returned to the system when freed. By
  // default glibc raises this threshold to the size of the first such array freed and then keeps
  // the neighbour lists that every rebuild frees in its heap: a bed of 10⁵ spheres held ≈ 10 %
  // more resident memory that way (bench/CHANGELOG.md, 2026-11-25, "Peak through a rebuild").
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  // Under mpirun (or another MPI launcher) the processes form one run; alone, MPI is not started.
  std::optional<granular::MpiSession> mpi;
  if (granular::MpiSession::launched()) mpi.emplace(argc, argv);
  granular::app::CommandLine commandLine(
      mpi ? std::shared_ptr<const granular::Communicator>(mpi->world()) : nullptr);
  return commandLine.run(argc, argv);
}
