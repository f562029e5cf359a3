#pragma once
/// The processes of a run split by space: a rank and a count, reductions that give the same
/// bits on every rank and for any rank count, and the exchange of byte buffers between ranks.
/// The interface lives in the base so that the engine can reduce over ranks; one process is
/// implemented here (singleProcess), MPI in core/parallel (granular/mpi_session.hpp), the only
/// code that includes mpi.h.
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
  /// Each integer summed over the ranks, in place.
  virtual void sumOverRanks(std::vector<std::uint64_t>& values) const = 0;
  /// One integer summed over the ranks.
  std::uint64_t sumOverRanks(std::uint64_t x) const {
    std::vector<std::uint64_t> v{x};
    sumOverRanks(v);
    return v[0];
  }
  /// Merges the ranks' accumulators into each rank's (ExactSum::words), and sums `counts` over
  /// the ranks, in one reduction: the same bits on every rank, whatever the split of the terms
  /// among them.
  virtual void mergeOverRanks(std::vector<ExactSum>& sums,
                              std::vector<std::uint64_t>& counts) const = 0;
  /// The same without counts.
  void mergeOverRanks(std::vector<ExactSum>& sums) const {
    std::vector<std::uint64_t> none;
    mergeOverRanks(sums, none);
  }

  /// Sends outgoing[r] to rank r (r may be this rank) and returns what each rank sent here,
  /// indexed by sender. outgoing has size() entries.
  virtual std::vector<std::vector<std::byte>> exchange(
      const std::vector<std::vector<std::byte>>& outgoing) const = 0;
  /// The same where each rank knows how many bytes every other will send it (incoming[r]): only
  /// the ranks with something to send or receive exchange messages, with no step to agree the
  /// sizes first (the ghosts' refresh each step). The sizes must be the senders' exactly.
  virtual std::vector<std::vector<std::byte>> exchangeKnown(
      const std::vector<std::vector<std::byte>>& outgoing,
      const std::vector<std::size_t>& incoming) const = 0;
  /// Rank 0's bytes, on every rank.
  virtual std::vector<std::byte> broadcast(const std::vector<std::byte>& fromRankZero) const = 0;

  /// The lowest rank's non-empty text, on every rank (empty if every rank's is): a finding that
  /// some ranks make and every rank must act on alike.
  std::string firstOverRanks(const std::string& mine) const;

  /// Waits until every rank has reached this point.
  virtual void barrier() const = 0;
  /// The same for a rank that may wait long (while rank 0 alone runs a command): it sleeps
  /// between looks instead of keeping a core busy.
  virtual void restingBarrier() const { barrier(); }
};

/// One process: rank 0 of 1; every reduction returns its argument.
std::unique_ptr<Communicator> singleProcess();

}  // namespace granular
