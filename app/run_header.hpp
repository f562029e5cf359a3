#pragma once
/// Pieces shared by the subcommands: number formatting, the run header, the walls a time series
/// carries, and the mapping of errors to exit codes.
#include <exception>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "granular/communicator.hpp"
#include "granular/scene.hpp"

namespace granular::app {

/// printf-style formatting of one number.
std::string format(const char* pattern, double value);

/// Σ m [kg].
double totalMass(const Particles& particles);

/// The header printed before a run: particles, mass, integrator, contact duration, friction path,
/// walls, stages and output folder.
void printHeader(std::ostream& out, const Scene& scene, const Simulation& sim,
                 const std::filesystem::path& outDir);
/// For a run that starts from a saved state (particles[i].type = "state"): the contacts it
/// starts with (pairs and walls overlapping, the largest overlap) and that their history starts
/// at zero. Prints nothing for a scene without one.
void printSavedStateStart(std::ostream& out, const Scene& scene, const Simulation& sim);

/// The walls whose reactions a time series carries: the box's, plus the top wall if a stage will
/// place it. Fixed before the run because CSV columns cannot be added later.
std::vector<std::string> reactionWallNames(const Scene& scene);

/// Creates `folder` and its parents (IoError naming it and the reason).
void createOutputFolder(const std::filesystem::path& folder);

/// Runs `body`, mapping exceptions to a message on stderr and an exit status: 2 for an invalid
/// scene, configuration or checkpoint, 3 for a broken state or a failed run check
/// (NumericalError), 1 for I/O and anything else, 128 + the signal's number for a stop by
/// SIGTERM or SIGINT (stop_signals.hpp).
int withErrorMapping(const std::function<int()>& body);

/// The exit status and the message withErrorMapping gives an exception.
struct ErrorReport {
  int status = 1;
  std::string message;
};
ErrorReport reportOf(const std::exception_ptr& error);

/// Ends a rank of a run under mpirun with `status` and no message: another rank says why.
struct SilentExit {
  int status = 1;
};

/// withErrorMapping for a run under mpirun: an error every rank meets alike (an invalid scene or
/// stage, a stop by a signal, a failed run check) is said once, by rank 0, and every rank ends
/// with its status; one that a rank meets alone (an I/O error, a broken particle of its own)
/// is said by that rank, naming it, and ends every rank at once (MpiSession::abortAll).
int withRanksErrorMapping(const Communicator& ranks, const std::function<int()>& body);

}  // namespace granular::app
