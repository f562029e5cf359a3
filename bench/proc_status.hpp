#pragma once
/// The benchmarks' reading of /proc/self/status (Linux): memory figures of this process.
#include <fstream>
#include <sstream>
#include <string>

namespace granular::bench {

/// A field of /proc/self/status ("VmRSS", "VmHWM") in bytes (the kernel reports kB); 0 if absent.
inline double statusBytes(const std::string& key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind(key + ":", 0) == 0) {
      std::istringstream fields(line.substr(key.size() + 1));
      double kb = 0;
      fields >> kb;
      return kb * 1024.0;
    }
  }
  return 0.0;
}

}  // namespace granular::bench
