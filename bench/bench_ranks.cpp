/// granular_bench_ranks: a frictional bed split by space among the ranks of an MPI job
/// (Simulation::splitAmong), timed; run it alone and under mpirun to compare ranks with threads:
///   OMP_NUM_THREADS=1 mpirun -np 2 granular_bench_ranks --n 100000 --threads 1
///   granular_bench_ranks --n 100000 --threads 2
/// The bed is bench_scale's (a dense random packing of the paper's radii, 12 lattice layers, in a
/// box with side walls and a floor), settled for --settle steps (split too, untimed), then timed
/// for --steps steps. Rank 0 prints a markdown row: particles, ranks, threads per rank, ms per
/// step, particle-steps per second, the bytes each rank sends per step (messages to other ranks,
/// counted by a Communicator that wraps the world's: the ghosts' refresh, the redistribution at
/// rebuilds and the reductions), the particles a rank holds (owned and ghosts, mean), and the
/// peak resident memory per particle held (VmHWM of the timed steps, from the mean rank).
/// --bed FILE keeps the settled bed: written there after settling when FILE does not exist, read
/// from it (no settling) when it does, so that several rows time one settled bed (the settling
/// is deterministic: the same file on any rank count; it records n, --settle and --layers and is
/// refused for others).
#include <malloc.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "granular/bricks.hpp"
#include "granular/mpi_session.hpp"
#include "granular/packings.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"
#include "proc_status.hpp"
#include "scale_bed_settling.hpp"

namespace {

using granular::Communicator;

using granular::bench::statusBytes;

/// The world's communicator, counting the bytes this rank sends to the others.
class CountingCommunicator : public Communicator {
 public:
  explicit CountingCommunicator(std::unique_ptr<Communicator> world) : world_(std::move(world)) {}
  int rank() const override { return world_->rank(); }
  int size() const override { return world_->size(); }
  double maxOverRanks(double x) const override {
    sent_ += others() * sizeof x;
    return world_->maxOverRanks(x);
  }
  bool anyOverRanks(bool x) const override {
    sent_ += others();
    return world_->anyOverRanks(x);
  }
  void sumOverRanks(std::vector<std::uint64_t>& values) const override {
    sent_ += others() * values.size() * sizeof(std::uint64_t);
    world_->sumOverRanks(values);
  }
  void mergeOverRanks(std::vector<granular::ExactSum>& sums,
                      std::vector<std::uint64_t>& counts) const override {
    sent_ += others() * (sums.size() * (sizeof(granular::ExactSum::Words) + 2 * sizeof(double)) +
                         counts.size() * sizeof(std::uint64_t));
    world_->mergeOverRanks(sums, counts);
  }
  std::vector<std::vector<std::byte>> exchange(
      const std::vector<std::vector<std::byte>>& outgoing) const override {
    for (std::size_t r = 0; r < outgoing.size(); ++r) {
      if (static_cast<int>(r) != rank()) sent_ += outgoing[r].size();
    }
    return world_->exchange(outgoing);
  }
  std::vector<std::vector<std::byte>> exchangeKnown(
      const std::vector<std::vector<std::byte>>& outgoing,
      const std::vector<std::size_t>& incoming) const override {
    for (std::size_t r = 0; r < outgoing.size(); ++r) {
      if (static_cast<int>(r) != rank()) sent_ += outgoing[r].size();
    }
    return world_->exchangeKnown(outgoing, incoming);
  }
  std::vector<std::byte> broadcast(const std::vector<std::byte>& bytes) const override {
    return world_->broadcast(bytes);
  }
  void barrier() const override { world_->barrier(); }
  double sent() const { return sent_; }

 private:
  std::size_t others() const { return static_cast<std::size_t>(size() - 1); }
  std::unique_ptr<Communicator> world_;
  mutable double sent_ = 0;
};

struct Options {
  long n = 100000, settle = 1500, steps = 200, layers = 12, threads = 1;
  /// 0: the engine alone (no split, block sums: the one-process baseline); 1: split (also on
  /// one rank); 2: alone with exact sums.
  long mode = 1;
  std::string bed;  ///< --bed: the settled bed's file (empty: settle every time)
};

/// The settled bed's positions, radii and masses, with the options that made it.
struct BedHeader {
  long n, settle, layers;
};

bool readBed(const Options& o, granular::Particles& p) {
  std::ifstream in(o.bed, std::ios::binary);
  if (!in) return false;
  BedHeader h{};
  in.read(reinterpret_cast<char*>(&h), sizeof h);
  if (!in || h.n != o.n || h.settle != o.settle || h.layers != o.layers) {
    std::cerr << "granular_bench_ranks: " << o.bed << " holds another bed (n " << h.n << ", settle "
              << h.settle << ", layers " << h.layers << "); remove it\n";
    std::exit(2);
  }
  const std::size_t n = static_cast<std::size_t>(h.n);
  p.position.resize(n);
  p.radius.resize(n);
  p.mass.resize(n);
  in.read(reinterpret_cast<char*>(p.position.data()), std::streamsize(n * sizeof(granular::Vec3)));
  in.read(reinterpret_cast<char*>(p.radius.data()), std::streamsize(n * sizeof(double)));
  in.read(reinterpret_cast<char*>(p.mass.data()), std::streamsize(n * sizeof(double)));
  if (!in) {
    std::cerr << "granular_bench_ranks: " << o.bed << " is cut short; remove it\n";
    std::exit(2);
  }
  p.velocity.assign(n, granular::Vec3::Zero());
  p.angularVelocity.assign(n, granular::Vec3::Zero());
  return true;
}

void writeBed(const Options& o, const granular::Particles& p) {
  const std::string part = o.bed + ".part";
  std::ofstream out(part, std::ios::binary);
  const BedHeader h{o.n, o.settle, o.layers};
  out.write(reinterpret_cast<const char*>(&h), sizeof h);
  out.write(reinterpret_cast<const char*>(p.position.data()),
            std::streamsize(p.size() * sizeof(granular::Vec3)));
  out.write(reinterpret_cast<const char*>(p.radius.data()),
            std::streamsize(p.size() * sizeof(double)));
  out.write(reinterpret_cast<const char*>(p.mass.data()),
            std::streamsize(p.size() * sizeof(double)));
  out.close();
  if (!out || std::rename(part.c_str(), o.bed.c_str()) != 0) {
    std::cerr << "granular_bench_ranks: could not write " << o.bed << "\n";
    std::exit(1);
  }
}

Options parse(int argc, char** argv) {
  Options o;
  for (int k = 1; k + 1 < argc; k += 2) {
    const std::string arg = argv[k];
    if (arg == "--bed") {
      o.bed = argv[k + 1];
      continue;
    }
    const long value = std::strtol(argv[k + 1], nullptr, 10);  // --mode: 1 alone, 2 split,
                                                               // 3 alone with exact sums
    if (value < 1) {
      std::cerr << "granular_bench_ranks: " << arg << " must be >= 1\n";
      std::exit(2);
    }
    if (arg == "--n") {
      o.n = value;
    } else if (arg == "--settle") {
      o.settle = value;
    } else if (arg == "--steps") {
      o.steps = value;
    } else if (arg == "--layers") {
      o.layers = value;
    } else if (arg == "--threads") {
      o.threads = value;
    } else if (arg == "--mode" && value <= 3) {
      o.mode = value - 1;
    } else {
      std::cerr << "usage: granular_bench_ranks [--n N] [--settle S] [--steps T] [--layers L] "
                   "[--threads P] [--mode 1|2|3] [--bed FILE]\n";
      std::exit(2);
    }
  }
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  mallopt(M_MMAP_THRESHOLD, 1 << 20);
  std::optional<granular::MpiSession> mpi;
  if (granular::MpiSession::launched()) mpi.emplace(argc, argv);
  const Options o = parse(argc, argv);
  auto counting =
      std::make_shared<CountingCommunicator>(mpi ? mpi->world() : granular::singleProcess());
  const Communicator& world = *counting;
  const bool root = world.rank() == 0;

  granular::PackingLayout layout;
  const double perSide = std::sqrt(2.0 * static_cast<double>(o.n) / static_cast<double>(o.layers));
  layout.aspect = granular::Vec3(1.0, 1.0, 2.0 * static_cast<double>(o.n) / std::pow(perSide, 3));
  granular::BoxSpec box;
  granular::Particles particles =
      granular::denseRandomPacking(static_cast<std::size_t>(o.n), 0.030, 0.035,
                                   granular::Material{}.density, 20261123, &box, layout);
  granular::SimulationConfig config;
  config.material.friction = 0.3;
  config.timeStep = 1e-4;
  config.threads = static_cast<int>(o.threads);
  auto bricks = [&](const granular::Particles& p) {
    auto b = std::make_shared<granular::Bricks>(world.size(), box.min, box.max);
    b->balance(p.position, 0.07);
    return b;
  };
  if (o.bed.empty() || !readBed(o, particles)) {
    // Settled as bench_scale settles (scale_bed_settling.hpp), split, then gathered.
    granular::Simulation settle(particles, granular::buildWalls(box),
                                granular::bench::settlingConfig(config));
    settle.splitAmong(bricks(particles), counting);
    settle.run(static_cast<std::uint64_t>(o.settle));
    particles = settle.wholeState().particles();
    if (!o.bed.empty() && root) writeBed(o, particles);
  }
  std::fill(particles.velocity.begin(), particles.velocity.end(), granular::Vec3::Zero());
  std::fill(particles.angularVelocity.begin(), particles.angularVelocity.end(),
            granular::Vec3::Zero());
  granular::Simulation sim(particles, granular::buildWalls(box), config);
  if (o.mode == 1) sim.splitAmong(bricks(particles), counting);
  if (o.mode == 2) sim.setExactSums(true);
  particles = granular::Particles{};  // the timed peak holds this rank's share only
  sim.run(2);                         // warm the caches and the thread pool
  malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";  // the peak of the timed steps only
  const double sentBefore = counting->sent();
  world.barrier();
  const auto start = std::chrono::steady_clock::now();
  sim.run(static_cast<std::uint64_t>(o.steps));
  world.barrier();
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double sent = (counting->sent() - sentBefore) / static_cast<double>(o.steps);
  const double held = static_cast<double>(sim.particles().size());
  const double peak = statusBytes("VmHWM");
  // Means over the ranks (sums of integers, exact): bytes sent, particles held, peak memory.
  std::vector<std::uint64_t> sums{static_cast<std::uint64_t>(sent),
                                  static_cast<std::uint64_t>(held),
                                  static_cast<std::uint64_t>(peak)};
  world.sumOverRanks(sums);
  const double ranks = world.size();
  if (root) {
    const char* mode[] = {"alone", "split", "alone, exact sums"};
    std::printf("| %ld | %d (%s) | %ld | %.2f | %.3g M | %.0f | %.0f | %.0f |\n", o.n, world.size(),
                mode[o.mode], o.threads, 1e3 * wall / static_cast<double>(o.steps),
                static_cast<double>(o.n) * static_cast<double>(o.steps) / wall / 1e6,
                static_cast<double>(sums[0]) / ranks, static_cast<double>(sums[1]) / ranks,
                static_cast<double>(sums[2]) / static_cast<double>(sums[1]));
  }
  return 0;
}
