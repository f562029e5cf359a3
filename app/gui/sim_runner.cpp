#include "sim_runner.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <string_view>
#include <utility>

#include "granular/checkpoint.hpp"
#include "granular/contact_theory.hpp"
#include "granular/error.hpp"
#include "granular/scene_fingerprint.hpp"
#include "granular/stage.hpp"
#include "granular/stress.hpp"

namespace granular::gui {

namespace {

using Clock = std::chrono::steady_clock;

/// Keeps every other point once a series is full, so a long run still fits.
void halve(std::vector<float>& v) {
  std::size_t k = 0;
  for (std::size_t i = 0; i < v.size(); i += 2) v[k++] = v[i];
  v.resize(k);
}

/// Whether `sim` has the walls that Eq. (1) and (2) measure a box by (measureBox): a scene with
/// walls of its own instead (a silo, a drum) has no such box.
bool hasBoxWalls(const Simulation& sim) {
  return std::all_of(kBoxWallNames.begin(), kBoxWallNames.end(), [&](const char* name) {
    return std::string_view(name) == "top" || sim.findWall(name) >= 0;
  });
}

}  // namespace

void LiveSeries::clear() {
  for (std::vector<float>* v : {&time, &kinetic, &topForce, &bottomForce}) v->clear();
  for (int a = 0; a < 3; ++a) {
    eq1[a].clear();
    eq2[a].clear();
  }
}

SimRunner::SimRunner(const std::filesystem::path& scene) {
  build(scene);  // on this thread: a bad scene throws to the caller
  publish();
  thread_ = std::thread([this] { loop(); });
}

SimRunner::~SimRunner() {
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void SimRunner::build(const std::filesystem::path& scene) {
  Scene loaded = granular::loadScene(scene);
  Simulation sim = buildSimulation(loaded);
  if (!loaded.stages.empty()) beginStage(sim, loaded.stages.front());
  scene_ = std::move(loaded);
  sim_.emplace(std::move(sim));
  stage_ = 1;
  running_ = false;
  pendingSteps_ = 0;
  topWallVelocity_ = 0;
  if (scene_.stages.size() > 1) {
    for (const WallMotion& m : scene_.stages[1].wallMotions) {
      if (m.wall == "top") topWallVelocity_ = m.velocity.z();
    }
  }
  const EnergyBalance e = sim_->energy();
  energyStart_ = e.total();
  // Scale of the balance error: the potential energy the bed can lose falling one box height.
  double weight = 0;
  for (double m : sim_->particles().mass) weight += m * sim_->config().gravity.norm();
  energyScale_ =
      std::max(1e-300, weight * (scene_.box.max.z() - scene_.box.min.z()) + std::abs(e.total()));
  series_.clear();
  lastSample_ = -1;
  message_.clear();
  failedChecks_.clear();
  restartChecks();
}

void SimRunner::restartChecks() {
  checks_.emplace(scene_.output.checks, scene_.box, sim_->energy().total());
  lastCheck_ = sim_->time();
}

void SimRunner::checkAtSample() {
  const double t = sim_->time();
  // A stage that resets the clock starts the intervals again.
  if (t < lastCheck_) lastCheck_ = t;
  if (t - lastCheck_ < scene_.output.interval) return;
  lastCheck_ = t;
  const std::string stage = std::size_t(stage_) <= scene_.stages.size()
                                ? scene_.stages[std::size_t(stage_) - 1].name
                                : "stage " + std::to_string(stage_);
  try {
    for (std::string& found : checks_->atSample(*sim_, stage)) {
      failedChecks_.push_back(std::move(found));
    }
  } catch (const RunCheckError& e) {  // on_failed_check = "stop": the run stops here
    running_ = false;
    pendingSteps_ = 0;
    failedChecks_.push_back(e.what());
    message_ = e.what();
  }
}

void SimRunner::send(std::function<void()> command) {
  {
    std::lock_guard lock(mutex_);
    commands_.push_back(std::move(command));
    ++sent_;
  }
  wake_.notify_all();
}

void SimRunner::run() {
  send([this] { running_ = true; });
}
void SimRunner::pause() {
  send([this] {
    running_ = false;
    pendingSteps_ = 0;
  });
}
void SimRunner::step(int count) {
  send([this, count] {
    running_ = false;
    pendingSteps_ += std::max(0, count);
  });
}
void SimRunner::reset() {
  send([this] { build(scene_.sourceFile); });
}
void SimRunner::loadScene(const std::filesystem::path& scene) {
  send([this, scene] { build(scene); });
}
void SimRunner::startStage2() {
  send([this] {
    if (stage_ == 2) return;
    if (scene_.stages.size() < 2) throw ConfigError("this scene has no second stage");
    StageSpec stage = scene_.stages[1];
    for (WallMotion& m : stage.wallMotions) {
      if (m.wall == "top") m.velocity.z() = topWallVelocity_;
    }
    beginStage(*sim_, stage);
    stage_ = 2;
    if (stage.resetClock) {  // the plots follow the stage's own clock
      series_.clear();
      lastSample_ = -1;
    }
  });
}
void SimRunner::setStepsPerUpdate(int steps) {
  send([this, steps] { stepsPerUpdate_ = std::clamp(steps, 1, 100000); });
}
void SimRunner::setMaterial(const Material& material) {
  send([this, material] {
    sim_->setMaterial(material);
    // New stiffnesses change the elastic energy stored without work: the balance is measured
    // from the state with the new material.
    restartChecks();
  });
}
void SimRunner::setTopWallVelocity(double velocity) {
  send([this, velocity] {
    if (!std::isfinite(velocity)) throw ConfigError("top-wall velocity must be finite");
    topWallVelocity_ = velocity;
    const long top = sim_->findWall("top");
    if (top >= 0) sim_->setWallVelocity(std::size_t(top), Vec3(0.0, 0.0, velocity));
  });
}
void SimRunner::setIntegrator(Integrator integrator, double timeStep, bool automatic) {
  send([this, integrator, timeStep, automatic] {
    StepControl control = sim_->config().step;
    if (automatic) {
      sim_->setIntegrator(integrator);  // the step is re-chosen for it
      control.automatic = true;
      sim_->setStepControl(control);
      return;
    }
    if (!(timeStep > 0.0)) throw ConfigError("time step must be > 0");
    // The engine refuses a step above the network's (or, with no contact, the binary limit)
    // with the reason: change nothing unless the step suits the new integrator.
    control.automatic = false;
    const Integrator before = sim_->config().integrator;
    const double stepBefore = sim_->config().timeStep;
    sim_->setStepControl(control);
    if (timeStep < stepBefore) sim_->setTimeStep(timeStep);
    try {
      sim_->setIntegrator(integrator);
      sim_->setTimeStep(timeStep);
    } catch (...) {
      sim_->setIntegrator(before);
      sim_->setTimeStep(stepBefore);
      throw;
    }
  });
}
void SimRunner::saveCheckpoint(const std::filesystem::path& file) {
  send([this, file] {
    writeCheckpoint(*sim_, file, fingerprintScene(scene_), std::to_string(stage_));
    message_ = "saved " + file.string();
  });
}
void SimRunner::loadCheckpoint(const std::filesystem::path& file) {
  send([this, file] {
    CheckpointContents c = readCheckpointWithData(file, fingerprintScene(scene_));
    sim_.emplace(std::move(c.simulation));
    stage_ = c.appData == "2" || sim_->findWall("top") >= 0 ? 2 : 1;
    energyStart_ = sim_->energy().total();
    running_ = false;
    pendingSteps_ = 0;
    series_.clear();
    lastSample_ = -1;
    failedChecks_.clear();
    restartChecks();
    message_ = "loaded " + file.string();
  });
}

bool SimRunner::latest(Snapshot& out) {
  std::lock_guard lock(mutex_);
  if (published_.version == out.version) return false;
  out = published_;
  return true;
}

std::uint64_t SimRunner::steps() const {
  std::lock_guard lock(mutex_);
  return stepsPublished_;
}

void SimRunner::flush() {
  std::unique_lock lock(mutex_);
  const std::uint64_t target = sent_;
  done_.wait(lock, [&] { return carried_ >= target; });
}

void SimRunner::loop() {
  for (;;) {
    std::deque<std::function<void()>> commands;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock,
                 [&] { return quit_ || !commands_.empty() || running_ || pendingSteps_ > 0; });
      if (quit_) return;
      commands.swap(commands_);
    }
    for (auto& command : commands) {
      try {
        command();
      } catch (const std::exception& e) {
        message_ = e.what();
      }
    }
    if (running_ || pendingSteps_ > 0) {
      const int n = running_ ? stepsPerUpdate_ : std::min(pendingSteps_, stepsPerUpdate_);
      const auto start = Clock::now();
      try {
        sim_->run(std::uint64_t(n));
        checkAtSample();
      } catch (const std::exception& e) {  // a broken state: stop, say why, keep the window
        running_ = false;
        message_ = e.what();
      }
      rateSteps_ += n;
      rateSeconds_ += std::chrono::duration<double>(Clock::now() - start).count();
      if (!running_) pendingSteps_ = std::max(0, pendingSteps_ - n);
    }
    // At most ~60 pictures a second while running; always after commands or when stopping.
    const auto now = Clock::now();
    if (!commands.empty() || !(running_ || pendingSteps_ > 0) ||
        now - lastPublish_ >= std::chrono::milliseconds(15)) {
      publish();
      lastPublish_ = now;
    }
    {
      std::lock_guard lock(mutex_);
      carried_ += commands.size();
    }
    done_.notify_all();
  }
}

void SimRunner::publish() {
  const Simulation& sim = *sim_;
  Snapshot s;
  s.sceneFile = scene_.sourceFile.string();
  const Particles& p = sim.particles();
  s.centres = p.position;
  s.radii = p.radius;
  // Σ|F| and σ33 per particle as the analysis layer defines them, from one visit of the contacts.
  ParticleMeasures measures = particleMeasures(sim);
  s.forceSum = std::move(measures.forceSums);
  s.stress33.resize(p.size());
  s.speed.resize(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    s.stress33[i] = measures.stresses[i](2, 2);
    s.speed[i] = p.velocity[i].norm();
  }
  s.boxMin = scene_.box.min;
  s.boxMax = scene_.box.max;
  s.walls = sim.walls();
  if (const long top = sim.findWall("top"); top >= 0) {
    s.topWallZ = sim.walls()[std::size_t(top)].point.z();
  }
  s.time = sim.time();
  s.steps = sim.stepCount();
  if (rateSeconds_ > 0.2) {  // steps per second of stepping, over at least 0.2 s of it
    stepsPerSecond_ = rateSteps_ / rateSeconds_;
    rateSteps_ = rateSeconds_ = 0;
  }
  s.stepsPerSecond = stepsPerSecond_;
  s.particleContacts = sim.counters().particleContacts;
  s.wallContacts = sim.counters().wallContacts;
  s.stage = stage_;
  s.running = running_;
  const EnergyBalance e = sim.energy();
  s.kinetic = e.kinetic();
  s.energyBalanceError = (e.total() - energyStart_) / energyScale_;
  s.material = sim.config().material;
  s.integrator = sim.config().integrator;
  s.timeStep = sim.config().timeStep;
  const StepCheck& check = sim.stepCheck();
  s.maxTimeStep = check.contacts > 0 ? check.networkStep
                                     : maxStableStep(sim.contactScale(), sim.config().integrator);
  s.automaticStep = sim.config().step.automatic;
  s.smallestStep = sim.counters().smallestStep;
  s.largestStep = sim.counters().largestStep;
  s.topWallVelocity = topWallVelocity_;
  s.stepsPerUpdate = stepsPerUpdate_;
  s.message = message_;
  s.failedChecks = failedChecks_;

  // The plots: a sample at most every 1/400 of a simulated second.
  if (lastSample_ < 0 || s.time - lastSample_ >= 2.5e-3 || s.time < lastSample_) {
    lastSample_ = s.time;
    series_.time.push_back(float(s.time));
    series_.kinetic.push_back(float(s.kinetic));
    if (hasBoxWalls(sim)) {  // without them, the box's series stay empty
      const BoxStress box = measureBox(sim);
      series_.topForce.push_back(float(box.topForce));
      series_.bottomForce.push_back(float(box.bottomForce));
      for (int a = 0; a < 3; ++a) {
        series_.eq1[a].push_back(float(box.eq1(a, a)));
        series_.eq2[a].push_back(float(box.eq2[a]));
      }
    }
    if (series_.time.size() >= LiveSeries::kMaxPoints) {
      for (std::vector<float>* v :
           {&series_.time, &series_.kinetic, &series_.topForce, &series_.bottomForce}) {
        halve(*v);
      }
      for (int a = 0; a < 3; ++a) {
        halve(series_.eq1[a]);
        halve(series_.eq2[a]);
      }
    }
  }
  s.series = series_;
  std::lock_guard lock(mutex_);
  s.version = ++version_;
  stepsPublished_ = s.steps;
  published_ = std::move(s);
}

}  // namespace granular::gui
