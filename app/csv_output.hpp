#pragma once
/// CSV files written by `granular run`: the time series, particle states (snapshots and the final
/// state) and helpers shared by them. Numbers are written in the shortest form that reads back to
/// the same double, so no precision is lost.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "granular/error.hpp"
#include "granular/output_file.hpp"
#include "granular/simulation.hpp"

namespace granular::app {

/// Shortest round-trip decimal of x ("0.1", "1e-05").
std::string csvNumber(double x);

/// One row per sample: stage, time, step, the energy balance, contact counts and every wall's
/// reaction. Each row is written at once and whole (AppendFile), so that a crash loses nothing
/// already sampled and a full disk never leaves half a row.
class TimeSeriesWriter {
 public:
  /// `walls` fixes the reaction columns; a wall that does not exist yet (the top wall before
  /// it is placed) gets empty cells. The energy columns are those of the terms `material` uses
  /// (energyColumns(material)), as Simulation::energy() gives them.
  /// With `exchange` (a scene whose stages insert or remove particles) each row ends with the
  /// particles held, the masses held, inserted and discharged, their balance (zero, exactly)
  /// and the energy exchanged (Simulation::particleTally, EnergyBalance::exchanged).
  TimeSeriesWriter(const std::filesystem::path& path, std::vector<std::string> walls,
                   const Material& material, bool exchange = false);
  /// Continues a file written up to `bytes` (a resumed run): rows after that are dropped, so the
  /// file ends as if the run had never stopped. IoError if the file is shorter; ConfigError,
  /// nothing cut, if its first `bytes` do not hash to `hash` (they were edited).
  TimeSeriesWriter(const std::filesystem::path& path, std::vector<std::string> walls,
                   std::uint64_t bytes, std::optional<std::uint64_t> hash, bool exchange = false);
  /// Collective in a split run (the energies and the tally are summed over the ranks).
  void write(const std::string& stage, const Simulation& sim);
  /// Bytes in the file so far (every row is written as it comes) [B].
  std::uint64_t bytes() const { return file_.bytes(); }
  /// FNV-1a of those bytes.
  std::uint64_t hash() const { return file_.contentHash(); }
  /// Waits until every row is on the disk (before a checkpoint that counts them).
  void sync() { file_.sync(); }

 private:
  AppendFile file_;
  std::vector<std::string> walls_;
  bool exchange_ = false;
};

/// Writes id,x,y,z,vx,vy,vz,wx,wy,wz,radius,mass (SI units) to a temporary file renamed into
/// place, so a reader never sees half a file.
/// `ids`: each particle's id (a rank's share of a split run), else its index.
void writeParticleState(const std::filesystem::path& path, const Particles& particles,
                        const std::vector<std::uint64_t>* ids = nullptr);
/// The same columns, then step and time_s: the step the state was written at and the simulation
/// clock, the same on every row (a snapshot's name gives the step only).
void writeParticleSnapshot(const std::filesystem::path& path, const Simulation& sim);

/// Writes `text` to `path` through a temporary file and a rename (writeFileAtomically).
void writeTextFile(const std::filesystem::path& path, const std::string& text);

}  // namespace granular::app
