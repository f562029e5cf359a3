#pragma once
/// The processes of a run split by space, as the engine's parallel layer sees them: a rank and a
/// count, reductions that give the same bits on every rank and for any rank count, and the
/// exchange of byte buffers between ranks. One implementation runs one process (always built);
/// the other runs on MPI (built where CMake finds MPI, GRANULAR_MPI). Nothing here includes
/// mpi.h, so the layer's users build without MPI's headers.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "granular/exact_sum.hpp"

namespace granular {

class Communicator {
 public:
  virtual ~Communicator() = default;
  /// This process's rank, 0 <= rank() < size().
  virtual int rank() const = 0;
  /// How many processes the run has.
  virtual int size() const = 0;

  /// The largest x over the ranks (exact: the same bits on every rank).
  virtual double maxOverRanks(double x) const = 0;
  /// Whether any rank passes true.
  virtual bool anyOverRanks(bool x) const = 0;
  /// The sum of an integer over the ranks.
  virtual std::uint64_t sumOverRanks(std::uint64_t x) const = 0;
  /// Merges the ranks' accumulators into each rank's (ExactSum::words): the same bits on every
  /// rank, whatever the split of the terms among them.
  virtual void mergeOverRanks(std::vector<ExactSum>& sums) const = 0;

  /// Sends outgoing[r] to rank r (r may be this rank) and returns what each rank sent here,
  /// indexed by sender. outgoing has size() entries.
  virtual std::vector<std::vector<std::byte>> exchange(
      const std::vector<std::vector<std::byte>>& outgoing) const = 0;
  /// Rank 0's bytes, on every rank.
  virtual std::vector<std::byte> broadcast(const std::vector<std::byte>& fromRankZero) const = 0;

  /// Waits until every rank has reached this point.
  virtual void barrier() const = 0;
};

/// One process: rank 0 of 1; every reduction returns its argument.
std::unique_ptr<Communicator> singleProcess();

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
  /// The world's processes: MPI_COMM_WORLD, or singleProcess() without MPI.
  std::unique_ptr<Communicator> world() const;
  /// Ends every rank of the run at once with `code` (MPI_Abort): for an error one rank found
  /// that the others cannot know of. Without MPI, exits the process.
  [[noreturn]] static void abortAll(int code);
};

}  // namespace granular
