/// The communicator of a run on one process (granular/communicator.hpp).
#include "granular/communicator.hpp"

namespace granular {
namespace {

class SingleProcess final : public Communicator {
 public:
  int rank() const override { return 0; }
  int size() const override { return 1; }
  double maxOverRanks(double x) const override { return x; }
  bool anyOverRanks(bool x) const override { return x; }
  void sumOverRanks(std::vector<std::uint64_t>&) const override {}
  void mergeOverRanks(std::vector<ExactSum>&, std::vector<std::uint64_t>&) const override {}
  std::vector<std::vector<std::byte>> exchange(
      const std::vector<std::vector<std::byte>>& outgoing) const override {
    return outgoing;
  }
  std::vector<std::vector<std::byte>> exchangeKnown(
      const std::vector<std::vector<std::byte>>& outgoing,
      const std::vector<std::size_t>&) const override {
    return outgoing;
  }
  std::vector<std::byte> broadcast(const std::vector<std::byte>& bytes) const override {
    return bytes;
  }
  void barrier() const override {}
};

}  // namespace

std::unique_ptr<Communicator> singleProcess() {
  return std::make_unique<SingleProcess>();
}

}  // namespace granular
