/// The communicator on MPI (granular/communicator.hpp) and the MPI session
/// (granular/mpi_session.hpp). Built with or without MPI: without it (GRANULAR_WITH_MPI
/// undefined) the session does nothing and the world is one process.
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "granular/mpi_session.hpp"

#ifdef GRANULAR_WITH_MPI
#include <mpi.h>
#endif

namespace granular {

#ifdef GRANULAR_WITH_MPI
namespace {

/// Throws on an MPI error code (MPI's default handler aborts first; this is for the others).
void check(int code, const char* what) {
  if (code != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

class MpiCommunicator final : public Communicator {
 public:
  explicit MpiCommunicator(MPI_Comm comm) : comm_(comm) {
    check(MPI_Comm_rank(comm_, &rank_), "MPI_Comm_rank");
    check(MPI_Comm_size(comm_, &size_), "MPI_Comm_size");
  }
  int rank() const override { return rank_; }
  int size() const override { return size_; }

  double maxOverRanks(double x) const override {
    double out = x;
    check(MPI_Allreduce(&x, &out, 1, MPI_DOUBLE, MPI_MAX, comm_), "MPI_Allreduce (max)");
    return out;
  }
  bool anyOverRanks(bool x) const override {
    int in = x ? 1 : 0, out = 0;
    check(MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_LOR, comm_), "MPI_Allreduce (or)");
    return out != 0;
  }
  void sumOverRanks(std::vector<std::uint64_t>& values) const override {
    check(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_UINT64_T,
                        MPI_SUM, comm_),
          "MPI_Allreduce (sum)");
  }
  void mergeOverRanks(std::vector<ExactSum>& sums,
                      std::vector<std::uint64_t>& counts) const override {
    // One reduction of integers: per accumulator its carried limbs and count (ExactSum::words),
    // summed element by element, and its special-value flags as three 0/1 counters (summed,
    // then nonzero: the flags ORed); then the counts. Integer sums in any order: the merge of
    // every rank's accumulator.
    constexpr std::size_t kSummed = ExactSum::kLimbs + 1, kFlags = 3;
    constexpr std::size_t kPer = kSummed + kFlags;
    const std::size_t n = sums.size();
    std::vector<std::int64_t> words(n * kPer + counts.size());
    for (std::size_t k = 0; k < n; ++k) {
      const ExactSum::Words w = sums[k].words();
      std::int64_t* at = words.data() + k * kPer;
      std::copy(w.begin(), w.begin() + kSummed, at);
      for (std::size_t f = 0; f < kFlags; ++f) at[kSummed + f] = (w[kSummed] >> f) & 1;
    }
    for (std::size_t c = 0; c < counts.size(); ++c) {
      words[n * kPer + c] = static_cast<std::int64_t>(counts[c]);
    }
    check(MPI_Allreduce(MPI_IN_PLACE, words.data(), static_cast<int>(words.size()), MPI_INT64_T,
                        MPI_SUM, comm_),
          "MPI_Allreduce (exact sums)");
    for (std::size_t k = 0; k < n; ++k) {
      const std::int64_t* at = words.data() + k * kPer;
      ExactSum::Words w{};
      std::copy(at, at + kSummed, w.begin());
      for (std::size_t f = 0; f < kFlags; ++f) {
        if (at[kSummed + f] != 0) w[kSummed] |= std::int64_t{1} << f;
      }
      sums[k] = ExactSum::fromWords(w);
    }
    for (std::size_t c = 0; c < counts.size(); ++c) {
      counts[c] = static_cast<std::uint64_t>(words[n * kPer + c]);
    }
  }
  std::vector<std::vector<std::byte>> exchangeKnown(
      const std::vector<std::vector<std::byte>>& outgoing,
      const std::vector<std::size_t>& incoming) const override {
    if (static_cast<int>(outgoing.size()) != size_ || static_cast<int>(incoming.size()) != size_) {
      throw std::invalid_argument("exchange: one buffer and one size per rank expected");
    }
    // Point to point, with the ranks that have something to send or receive only.
    constexpr int kTag = 24;
    std::vector<std::vector<std::byte>> in(static_cast<std::size_t>(size_));
    std::vector<MPI_Request> requests;
    for (int r = 0; r < size_; ++r) {
      const std::size_t k = static_cast<std::size_t>(r);
      if (r == rank_) {
        in[k] = outgoing[k];
      } else if (incoming[k] > 0) {
        in[k].resize(incoming[k]);
        requests.emplace_back();
        check(MPI_Irecv(in[k].data(), static_cast<int>(incoming[k]), MPI_BYTE, r, kTag, comm_,
                        &requests.back()),
              "MPI_Irecv");
      }
    }
    for (int r = 0; r < size_; ++r) {
      const std::size_t k = static_cast<std::size_t>(r);
      if (r == rank_ || outgoing[k].empty()) continue;
      requests.emplace_back();
      check(MPI_Isend(outgoing[k].data(), static_cast<int>(outgoing[k].size()), MPI_BYTE, r, kTag,
                      comm_, &requests.back()),
            "MPI_Isend");
    }
    check(MPI_Waitall(static_cast<int>(requests.size()), requests.data(), MPI_STATUSES_IGNORE),
          "MPI_Waitall");
    return in;
  }
  std::vector<std::vector<std::byte>> exchange(
      const std::vector<std::vector<std::byte>>& outgoing) const override {
    if (static_cast<int>(outgoing.size()) != size_) {
      throw std::invalid_argument("exchange: one buffer per rank expected");
    }
    std::vector<int> sendCount(size_), receiveCount(size_), sendAt(size_), receiveAt(size_);
    int sendTotal = 0;
    for (int r = 0; r < size_; ++r) {
      sendCount[r] = static_cast<int>(outgoing[r].size());
      sendAt[r] = sendTotal;
      sendTotal += sendCount[r];
    }
    check(MPI_Alltoall(sendCount.data(), 1, MPI_INT, receiveCount.data(), 1, MPI_INT, comm_),
          "MPI_Alltoall (counts)");
    int receiveTotal = 0;
    for (int r = 0; r < size_; ++r) {
      receiveAt[r] = receiveTotal;
      receiveTotal += receiveCount[r];
    }
    std::vector<std::byte> send(static_cast<std::size_t>(sendTotal)),
        receive(static_cast<std::size_t>(receiveTotal));
    for (int r = 0; r < size_; ++r) {
      std::copy(outgoing[r].begin(), outgoing[r].end(), send.begin() + sendAt[r]);
    }
    check(MPI_Alltoallv(send.data(), sendCount.data(), sendAt.data(), MPI_BYTE, receive.data(),
                        receiveCount.data(), receiveAt.data(), MPI_BYTE, comm_),
          "MPI_Alltoallv");
    std::vector<std::vector<std::byte>> incoming(size_);
    for (int r = 0; r < size_; ++r) {
      incoming[r].assign(receive.begin() + receiveAt[r],
                         receive.begin() + receiveAt[r] + receiveCount[r]);
    }
    return incoming;
  }

  std::vector<std::byte> broadcast(const std::vector<std::byte>& bytes) const override {
    std::uint64_t size = bytes.size();
    check(MPI_Bcast(&size, 1, MPI_UINT64_T, 0, comm_), "MPI_Bcast (size)");
    std::vector<std::byte> out = rank_ == 0 ? bytes : std::vector<std::byte>(size);
    check(MPI_Bcast(out.data(), static_cast<int>(size), MPI_BYTE, 0, comm_), "MPI_Bcast");
    return out;
  }

  void barrier() const override { check(MPI_Barrier(comm_), "MPI_Barrier"); }
  void restingBarrier() const override {
    MPI_Request request;
    check(MPI_Ibarrier(comm_, &request), "MPI_Ibarrier");
    for (;;) {
      int done = 0;
      check(MPI_Test(&request, &done, MPI_STATUS_IGNORE), "MPI_Test");
      if (done) return;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }

 private:
  MPI_Comm comm_;
  int rank_ = 0, size_ = 1;
};

}  // namespace

bool builtWithMpi() {
  return true;
}

MpiSession::MpiSession(int& argc, char**& argv) {
  int provided = 0;
  check(MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
}

MpiSession::~MpiSession() {
  MPI_Finalize();
}

std::unique_ptr<Communicator> MpiSession::world() const {
  return std::make_unique<MpiCommunicator>(MPI_COMM_WORLD);
}

void MpiSession::abortAll(int code) {
  MPI_Abort(MPI_COMM_WORLD, code);
  std::_Exit(code);  // MPI_Abort does not return; should it, the process still ends
}

#else  // one process

bool builtWithMpi() {
  return false;
}

MpiSession::MpiSession(int&, char**&) {}
MpiSession::~MpiSession() = default;

std::unique_ptr<Communicator> MpiSession::world() const {
  return singleProcess();
}

void MpiSession::abortAll(int code) {
  std::_Exit(code);
}

#endif

bool MpiSession::launched() {
  // OpenMPI's mpirun sets OMPI_COMM_WORLD_SIZE; PMIx and PMI launchers (srun, MPICH's
  // mpiexec) set theirs.
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"}) {
    if (std::getenv(name) != nullptr) return true;
  }
  return false;
}

}  // namespace granular
