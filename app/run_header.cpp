/// Shared pieces of the subcommands (run_header.hpp).
#include "run_header.hpp"

#include <cstdio>
#include <filesystem>
#include <iostream>

#include "csv_output.hpp"
#include "granular/checkpoint.hpp"
#include "granular/contact_model.hpp"
#include "granular/error.hpp"
#include "granular/mpi_session.hpp"
#include "stop_signals.hpp"

namespace granular::app {

std::string format(const char* pattern, double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, pattern, value);
  return buffer;
}

double totalMass(const Particles& particles) {
  double sum = 0.0;
  for (double m : particles.mass) sum += m;
  return sum;
}

namespace {

/// Which contact sets the step limit, said of what the scene can form: the limit assumes the
/// stiffer of a particle-particle and a particle-wall contact of the smallest radius, and a scene
/// of one sphere has no pair, a scene without walls no wall contact.
std::string contactKinds(const Scene& scene, const Simulation& sim) {
  const bool pairs = sim.particles().size() >= 2 || exchangesParticles(scene);
  bool walls = !sim.walls().empty();
  for (const StageSpec& stage : scene.stages) walls = walls || stage.placeTopWallOnSurface;
  const bool wallSets = sim.contactScale().againstWall;
  const std::string kind = wallSets ? "particle-wall" : "particle-particle";
  if (wallSets ? walls : pairs) return "stiffest " + kind;
  const std::string formed = pairs   ? "particle-particle contacts only"
                             : walls ? "particle-wall contacts only"
                                     : "no contacts (one sphere, no walls)";
  return formed + "; the step limit uses a " + kind + " contact, which this scene cannot form";
}

}  // namespace

void printHeader(std::ostream& out, const Scene& scene, const Simulation& sim,
                 const std::filesystem::path& outDir) {
  const SimulationConfig& config = sim.config();
  const ContactScale& contact = sim.contactScale();
  const double dt = config.timeStep;
  out << "scene       " << scene.sourceFile.string() << "\n";
  out << "particles   " << sim.particles().size() << ", total mass "
      << format("%.6g", totalMass(sim.particles())) << " kg (density "
      << format("%.6g", config.material.density) << " kg/m³"
      << (scene.totalMass ? ", scaled to the scene's total_mass" : "") << ")\n";
  for (const StageSpec& stage : scene.stages) {
    for (const InsertSpec& insert : stage.inserts) {
      out << "inserts     " << insert.name << ": " << insert.count << " in stage " << stage.name
          << " at " << format("%.6g", insert.rate) << " /s, radii "
          << format("%.6g", insert.radiusMin) << "-" << format("%.6g", insert.radiusMax)
          << " m, every " << format("%.6g", stage.exchangeInterval) << " s\n";
    }
    for (const OutletSpec& outlet : stage.outlets) {
      out << "outlets     " << outlet.name << " in stage " << stage.name << ", every "
          << format("%.6g", stage.exchangeInterval) << " s\n";
    }
    if (!stage.removeWalls.empty()) {
      out << "removes     ";
      for (const std::string& wall : stage.removeWalls) out << wall << ' ';
      out << "at the start of stage " << stage.name << "\n";
    }
  }
  // The step in full (it reads back to the same double): a rounded one hides a typo.
  const char* integrator = config.integrator == Integrator::Gear5 ? "gear5" : "verlet";
  const StepCheck& check = sim.stepCheck();
  if (config.step.automatic) {
    // The floor: t_c / contact_resolution, and for Gear5 also its own t_c/50 (measureStep).
    const bool gearLimit = config.integrator == Integrator::Gear5 &&
                           1.0 / kMaxStepFractionGear5 > config.step.contactResolution;
    const double resolution =
        gearLimit ? 1.0 / kMaxStepFractionGear5 : config.step.contactResolution;
    out << "integrator  " << integrator << ", dt = auto: " << format("%.4g", config.step.safety)
        << " x the contact network's stable step, at most duration/" << format("%g", resolution)
        << " = " << format("%.4g", sim.contactScale().duration / resolution) << " s"
        << (gearLimit ? " (gear5's own limit)"
                      : " while contacts strike (not move with the network)")
        << "; re-chosen at each neighbour-list rebuild "
        << "and every " << config.step.recheckSteps << " steps; first dt = " << csvNumber(dt)
        << " s ("
        << (check.contacts > 0 ? "network " + format("%.4g", check.networkStep) + " s from " +
                                     std::to_string(check.contacts) + " contacts"
                               : std::string("no contact yet: the accuracy floor"))
        << ")\n";
  } else {
    out << "integrator  " << integrator << ", dt = " << csvNumber(dt) << " s"
        << (check.contacts > 0
                ? ", the contact network allows " + format("%.4g", check.networkStep) + " s now"
                : std::string(""))
        << "; on_unstable = " << (config.step.onUnstable == OnUnstable::Stop ? "stop" : "warn")
        << "\n";
  }
  out << "contact     " << contactKinds(scene, sim) << " (R = " << format("%.4g", contact.radius)
      << " m), duration " << format("%.4g", contact.duration) << " s; dt = duration/"
      << format("%.1f", contact.duration / dt) << "\n";
  out << "friction    "
      << (sim.frictional() ? "on (mu = " + format("%g", config.material.friction) +
                                 "): tangential forces and rotations integrated"
                           : std::string("off (mu = 0): no tangential forces, no rotations"));
  if (sim.frictional() && config.material.tangentialLaw == TangentialLaw::Constant) {
    out << "; constant k_t = " << format("%.6g", config.material.tangentialStiffness) << " N/m";
  }
  out << "\n";
  // The optional terms of the contact model the material switches on (rolling resistance).
  std::string optional;
  for (const TermSpec& term : contactTerms()) {
    if (term.active && term.active(config.material)) optional.append(" ").append(term.name);
  }
  if (!optional.empty()) out << "terms      " << optional << " (optional terms in use)\n";
  if (config.exactSums) {
    out << "sums        exact (exact_sums = true): the energies and wall reactions are the bits "
           "of a run under mpirun\n";
  }
  out << "walls      ";
  for (const Wall& wall : sim.walls()) out << " " << wall.name;
  out << "\nstages     ";
  for (const StageSpec& stage : scene.stages) {
    out << " " << stage.name << " (<= " << format("%g", stage.end.maxTime) << " s)";
  }
  out << "\noutput      " << outDir.string() << " (sample every "
      << format("%g", scene.output.interval) << " s)\n"
      << std::flush;
}

void printSavedStateStart(std::ostream& out, const Scene& scene, const Simulation& sim) {
  std::string files;
  for (const Generator& g : scene.generators) {
    const auto* csv = std::get_if<CsvGenerator>(&g);
    if (csv && csv->savedState) files += (files.empty() ? "" : ", ") + csv->path.string();
  }
  if (files.empty()) return;
  std::size_t pairs = 0, walls = 0;
  double largest = 0.0, relative = 0.0;  // the largest overlap [m] and over its radius [-]
  sim.forEachContact([&](const ContactView& c) {
    if (!c.isWall() && c.otherParticle() < c.particle) return;  // each pair once
    if (!c.touching()) return;                                  // a liquid bridge across a gap
    (c.isWall() ? walls : pairs) += 1;
    double radius = sim.particles().radius[c.particle];
    if (!c.isWall()) radius = std::min(radius, sim.particles().radius[c.otherParticle()]);
    if (c.overlap > largest) largest = c.overlap;
    relative = std::max(relative, c.overlap / radius);
  });
  out << "start       saved state " << files << ": " << pairs << " particle and " << walls
      << " wall contacts overlapping, the largest by " << format("%.4g", largest) << " m ("
      << format("%.3g", 100.0 * relative) << " % of a radius); every contact's history (tangential"
      << (RollingResistance::active(sim.config().material) ? " and rolling" : "")
      << " springs) starts at zero: a state file does not hold it\n";
}

/// The walls whose reactions the time series carries: the box's, plus the top wall if a stage
/// will place it. Fixed before the run because CSV columns cannot be added later.
std::vector<std::string> reactionWallNames(const Scene& scene) {
  std::vector<std::string> walls;
  for (std::size_t f = 0; f < kBoxWallNames.size(); ++f) {
    if (scene.box.walls[f]) walls.push_back(kBoxWallNames[f]);
  }
  for (const Wall& wall : scene.walls) walls.push_back(wall.name);
  for (const StageSpec& stage : scene.stages) {
    if (stage.placeTopWallOnSurface && !scene.box.walls[5]) {
      walls.push_back("top");
      break;
    }
  }
  return walls;
}

void createOutputFolder(const std::filesystem::path& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) {
    throw IoError(folder.string() + ": cannot create the output folder: " + ec.message());
  }
}

ErrorReport reportOf(const std::exception_ptr& error) {
  try {
    std::rethrow_exception(error);
  } catch (const SceneError& e) {
    return {2, std::string("error: ") + e.what()};
  } catch (const ConfigError& e) {
    return {2, std::string("error: ") + e.what()};
  } catch (const CheckpointError& e) {
    return {2, std::string("error: ") + e.what()};
  } catch (const IoError& e) {
    return {1, std::string("error: ") + e.what()};
  } catch (const Interrupted& e) {
    return {128 + e.signal(), e.what()};
  } catch (const NumericalError& e) {  // a broken state or a failed run check: exit 3
    return {3, std::string("error: ") + e.what()};
  } catch (const std::bad_alloc&) {
    return {1, "error: out of memory (std::bad_alloc)"};
  } catch (const std::exception& e) {
    return {1, std::string("error: ") + e.what()};
  }
}

int withErrorMapping(const std::function<int()>& body) {
  try {
    return body();
  } catch (const SilentExit& e) {
    return e.status;
  } catch (...) {
    const ErrorReport report = reportOf(std::current_exception());
    std::cerr << report.message << "\n";
    return report.status;
  }
}

int withRanksErrorMapping(const Communicator& ranks, const std::function<int()>& body) {
  try {
    return body();
  } catch (const SilentExit& e) {
    return e.status;
  } catch (...) {
    const std::exception_ptr error = std::current_exception();
    const ErrorReport report = reportOf(error);
    bool alike = false;  // met by every rank at the same point of the run
    try {
      std::rethrow_exception(error);
    } catch (const SceneError&) {
      alike = true;
    } catch (const ConfigError&) {
      alike = true;
    } catch (const CheckpointError&) {
      alike = true;
    } catch (const Interrupted&) {
      alike = true;
    } catch (...) {
    }
    if (alike) {
      if (ranks.rank() == 0) std::cerr << report.message << "\n";
      return report.status;
    }
    std::cerr << report.message << " (rank " << ranks.rank() << " of " << ranks.size() << ")\n"
              << std::flush;
    if (ranks.size() > 1) MpiSession::abortAll(report.status);
    return report.status;
  }
}

}  // namespace granular::app
