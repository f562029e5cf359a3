/// Run progress records (run_progress.hpp).
#include "run_progress.hpp"

#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "granular/checkpoint.hpp"

namespace granular::app {

namespace {

constexpr const char* kTag = "granular-run-progress 1";

std::string hex(double x) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%a", x);
  return buffer;
}

/// Reads the whitespace-separated fields of one record line, refusing anything malformed.
class Fields {
 public:
  Fields(const std::string& line, const std::string& file) : in_(line), file_(file) {}
  std::string word() {
    std::string w;
    if (!(in_ >> w)) fail();
    return w;
  }
  double number() {
    const std::string w = word();
    char* end = nullptr;
    const double x = std::strtod(w.c_str(), &end);
    if (end != w.c_str() + w.size()) fail();
    return x;
  }
  std::uint64_t count() {
    const std::string w = word();
    char* end = nullptr;
    const unsigned long long n = std::strtoull(w.c_str(), &end, 10);
    if (w.empty() || w[0] == '-' || end != w.c_str() + w.size()) fail();
    return n;
  }
  [[noreturn]] void fail() const {
    throw CheckpointError(file_ + ": the run progress stored in the checkpoint is malformed");
  }

 private:
  std::istringstream in_;
  const std::string& file_;
};

}  // namespace

std::string encodeRunProgress(const RunProgress& p) {
  std::ostringstream out;
  out << kTag << "\n"
      << "stage " << p.stage << "\n"
      << "steps " << p.inStage.steps << "\n"
      << "below_since " << (p.inStage.belowSince ? hex(*p.inStage.belowSince) : "none") << "\n"
      << "series_bytes " << p.seriesBytes << "\n";
  if (p.energyReference) out << "energy_reference " << hex(*p.energyReference) << "\n";
  if (p.inStage.time) out << "stage_time " << hex(*p.inStage.time) << "\n";
  if (p.seriesHash) out << "series_hash " << *p.seriesHash << "\n";
  out << "stage_origin " << hex(p.stageOrigin) << "\n";
  for (const ParaviewFrame& f : p.frames) {
    out << "frame " << f.stage << " " << f.step << " " << hex(f.runTime) << "\n";
  }
  for (const FinishedStage& f : p.finished) {
    out << "finished " << (f.result.reason == StageEndReason::KineticEnergy ? "kinetic" : "time")
        << " " << hex(f.result.duration) << " " << f.result.steps << " " << hex(f.wallSeconds)
        << "\n";
  }
  return out.str();
}

RunProgress decodeRunProgress(const std::string& text, const std::string& file) {
  std::istringstream in(text);
  std::string line;
  auto next = [&](const char* key) {
    if (!std::getline(in, line)) Fields("", file).fail();
    Fields f(line, file);
    if (f.word() != key) f.fail();
    return f;
  };
  if (!std::getline(in, line) || line != kTag) Fields("", file).fail();
  RunProgress p;
  p.stage = next("stage").count();
  p.inStage.steps = next("steps").count();
  {
    Fields f = next("below_since");
    const std::string w = f.word();
    if (w != "none") p.inStage.belowSince = Fields(w, file).number();
  }
  p.seriesBytes = next("series_bytes").count();
  while (std::getline(in, line)) {
    Fields f(line, file);
    const std::string key = f.word();
    if (key == "energy_reference" && !p.energyReference && p.finished.empty()) {
      p.energyReference = f.number();
      continue;
    }
    if (key == "stage_time" && !p.inStage.time && p.finished.empty()) {
      p.inStage.time = f.number();
      continue;
    }
    if (key == "series_hash" && !p.seriesHash && p.finished.empty()) {
      p.seriesHash = f.count();
      continue;
    }
    if (key == "stage_origin" && p.finished.empty()) {
      p.stageOrigin = f.number();
      continue;
    }
    if (key == "frame") {
      ParaviewFrame frame;
      frame.stage = f.count();
      frame.step = f.count();
      frame.runTime = f.number();
      if (frame.stage > p.stage) f.fail();
      p.frames.push_back(frame);
      continue;
    }
    if (key != "finished") f.fail();
    FinishedStage s;
    const std::string reason = f.word();
    if (reason != "kinetic" && reason != "time") f.fail();
    s.result.reason = reason == "kinetic" ? StageEndReason::KineticEnergy : StageEndReason::MaxTime;
    s.result.duration = f.number();
    s.result.steps = f.count();
    s.wallSeconds = f.number();
    p.finished.push_back(s);
  }
  if (p.finished.size() != p.stage) Fields("", file).fail();
  return p;
}

}  // namespace granular::app
