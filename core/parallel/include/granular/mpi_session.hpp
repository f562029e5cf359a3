#pragma once
/// MPI for a program's life (core/parallel): the session that initialises and finalises it and
/// gives the world's Communicator. Built with or without MPI (GRANULAR_MPI); without it the
/// world is one process.
#include <memory>

#include "granular/communicator.hpp"

namespace granular {

/// Whether this build runs on MPI (GRANULAR_MPI).
bool builtWithMpi();

/// MPI for the life of the object: initialises it (threads funnelled through the main thread:
/// OpenMP threads compute, only the main thread communicates) and finalises it. One per
/// process, made first in main(). Without MPI it does nothing.
class MpiSession {
 public:
  MpiSession(int& argc, char**& argv);
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  /// Whether an MPI launcher (mpirun, mpiexec) started this process: its environment names the
  /// rank. A program started alone needs no MPI session.
  static bool launched();
  /// The world's processes: MPI_COMM_WORLD, or singleProcess() without MPI.
  std::unique_ptr<Communicator> world() const;
  /// Ends every rank of the run at once with `code` (MPI_Abort): for an error one rank found
  /// that the others cannot know of. Without MPI, exits the process.
  [[noreturn]] static void abortAll(int code);
};

}  // namespace granular
