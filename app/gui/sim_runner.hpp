#pragma once
/// The GUI's simulation, on a thread of its own: the window sends it commands and reads whole
/// snapshots, so the picture never mixes two states and a slow step never blocks a frame.
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <filesystem>
#include <functional>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "granular/run_checks.hpp"
#include "granular/scene.hpp"
#include "granular/simulation.hpp"

namespace granular::gui {

/// Time series for the live plots, sampled at most every `interval` of simulated time and
/// halved (every other point kept) when they reach `kMaxPoints`. The box's series (reactions,
/// Eq. (1) and (2)) stay empty in a scene without the box's walls.
struct LiveSeries {
  static constexpr std::size_t kMaxPoints = 4000;
  std::vector<float> time;                   ///< [s]
  std::vector<float> kinetic;                ///< kinetic energy [J]
  std::vector<float> topForce, bottomForce;  ///< R33 of the top and bottom walls [N]
  std::vector<float> eq1[3], eq2[3];         ///< σ11, σ22, σ33 by Eq. (1) and Eq. (2) [Pa]
  void clear();
};

/// One consistent picture of the run, published by the simulation thread.
struct Snapshot {
  std::uint64_t version = 0;  ///< grows with every publication
  std::string sceneFile;
  std::vector<Vec3> centres;     ///< [m]
  std::vector<double> radii;     ///< [m]
  std::vector<double> forceSum;  ///< Σ_j |F_ij| per particle [N]
  std::vector<double> speed;     ///< |v| per particle [m/s]
  /// σ33 of each particle, the zz entry of particleStresses: (1/V_i) Σ_c F_z (C_z − z_i) over its
  /// contacts, V_i its own volume (4/3 π R_i³) [Pa]; compression negative, as in the paper.
  std::vector<double> stress33;
  Vec3 boxMin = Vec3::Zero(), boxMax = Vec3::Ones();  ///< [m]
  std::optional<double> topWallZ;                     ///< [m], once stage 2 placed it
  double time = 0;                                    ///< simulated time [s]
  std::uint64_t steps = 0;
  double stepsPerSecond = 0;
  std::size_t particleContacts = 0, wallContacts = 0;
  int stage = 1;  ///< 1: settling under gravity, 2: compaction by the top wall
  bool running = false;
  double kinetic = 0;  ///< [J]
  /// Drift of the energy balance since the start (or the last load), over the energy a fall of
  /// the whole bed through the box height releases [-].
  double energyBalanceError = 0;
  Material material;
  Integrator integrator = Integrator::Gear5;
  double timeStep = 0;  ///< [s]
  /// The step the contact network allows (at the last check; with no contact yet, the
  /// binary limit for this integrator) [s].
  double maxTimeStep = 0;
  bool automaticStep = false;                ///< time_step = "auto"
  double smallestStep = 0, largestStep = 0;  ///< the steps taken since the start [s]
  double topWallVelocity = 0;                ///< vertical, of stage 2 [m/s]
  int stepsPerUpdate = 20;
  LiveSeries series;
  std::string message;  ///< the last refusal or error, for the status line
  /// What the run checks (run_checks.hpp: the energy balance against the scene's
  /// output.energy_drift_limit, particles outside the box) found since the start or the last
  /// load, oldest first; each check is reported once.
  std::vector<std::string> failedChecks;
  /// Every wall where the run has it now (the view draws all but the infinite planes).
  std::vector<Wall> walls;
};

class SimRunner {
 public:
  /// Loads `scene` (loadScene; SceneError/ConfigError propagate) and starts the thread paused.
  explicit SimRunner(const std::filesystem::path& scene);
  ~SimRunner();
  SimRunner(const SimRunner&) = delete;
  SimRunner& operator=(const SimRunner&) = delete;

  // Commands: queued, carried out by the simulation thread between steps. A refused one (a
  // value out of range, a step above the limit) leaves the run as it was and sets `message`.
  void run();
  void pause();
  void step(int count);  ///< that many steps, then paused
  void reset();          ///< the scene's initial state, stage 1
  void loadScene(const std::filesystem::path& scene);
  void startStage2();  ///< the scene's second stage set-up (top wall on the surface, its motion)
  void setStepsPerUpdate(int steps);
  void setMaterial(const Material& material);
  void setTopWallVelocity(double velocity);  ///< [m/s], negative moves it down
  /// The integrator and a fixed step (refused above what the contact network allows), or
  /// with `automatic` the step chosen from the network (time_step = "auto").
  void setIntegrator(Integrator integrator, double timeStep, bool automatic = false);
  void saveCheckpoint(const std::filesystem::path& file);
  void loadCheckpoint(const std::filesystem::path& file);

  /// Copies the newest snapshot into `out` if it is newer than out.version; returns whether.
  bool latest(Snapshot& out);
  /// Steps taken so far (cheap, for scripts waiting on the run).
  std::uint64_t steps() const;
  /// Blocks until every command sent so far has been carried out and published.
  void flush();

 private:
  void send(std::function<void()> command);
  void loop();
  void publish();
  void build(const std::filesystem::path& scene);
  /// New run checks measuring the energy balance from the state as it is now.
  void restartChecks();
  /// The run checks at each output interval of simulated time (scene.output.interval).
  void checkAtSample();

  mutable std::mutex mutex_;
  std::condition_variable wake_, done_;
  std::deque<std::function<void()>> commands_;
  std::uint64_t sent_ = 0, carried_ = 0;
  bool quit_ = false;
  Snapshot published_;
  std::uint64_t stepsPublished_ = 0;

  // Owned by the simulation thread.
  Scene scene_;
  std::optional<Simulation> sim_;
  bool running_ = false;
  int pendingSteps_ = 0;
  int stepsPerUpdate_ = 20;
  int stage_ = 1;
  double topWallVelocity_ = 0;
  double energyStart_ = 0, energyScale_ = 0;
  std::optional<RunChecks> checks_;
  double lastCheck_ = 0;  ///< simulated time of the last check [s]
  std::vector<std::string> failedChecks_;
  std::chrono::steady_clock::time_point lastPublish_;
  LiveSeries series_;
  double lastSample_ = -1;
  std::string message_;
  std::uint64_t version_ = 0;
  double rateSteps_ = 0, rateSeconds_ = 0, stepsPerSecond_ = 0;

  std::thread thread_;
};

}  // namespace granular::gui
