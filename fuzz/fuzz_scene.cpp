/// libFuzzer target for the scene loader (loadScene: toml++, the table reader, the key checks,
/// the particle CSV reader, the time-step check).
///
/// loadScene reads a file and has no in-memory entry point, so each input is written to a
/// private temporary folder (on /dev/shm when there is one, to keep it off the disk). An input
/// may carry a particle CSV file after a line "#---csv---": the part before it is the scene, the
/// part after it is written beside it as "particles.csv", so that a scene with
/// `file = "particles.csv"` gets the CSV reader fuzzed too.
///
/// Allowed outcomes: a scene, or the exceptions loadScene documents (SceneError, and the
/// ConfigError of the CSV reader and the contact theory). Anything else escaping is a bug: an
/// uncaught exception aborts and libFuzzer reports it as a crash.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>

#include "granular/error.hpp"
#include "granular/scene.hpp"

namespace {

std::filesystem::path folder;

void removeFolder() {
  std::error_code ignored;
  std::filesystem::remove_all(folder, ignored);
}

void writeFile(const std::filesystem::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  if (!out) {
    std::fprintf(stderr, "fuzz_scene: cannot write %s\n", path.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  std::error_code ec;
  const std::filesystem::path base = std::filesystem::is_directory("/dev/shm", ec)
                                         ? "/dev/shm"
                                         : std::filesystem::temp_directory_path();
  std::string pattern = (base / "granular-fuzz-scene-XXXXXX").string();
  if (!mkdtemp(pattern.data())) {
    std::perror("fuzz_scene: mkdtemp");
    std::abort();
  }
  folder = pattern;
  std::atexit(removeFolder);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view input(reinterpret_cast<const char*>(data), size);
  constexpr std::string_view kCsvMarker = "#---csv---\n";
  const std::size_t marker = input.find(kCsvMarker);
  const std::filesystem::path scene = folder / "scene.toml";
  const std::filesystem::path csv = folder / "particles.csv";
  writeFile(scene, input.substr(0, marker));
  if (marker != std::string_view::npos) {
    writeFile(csv, input.substr(marker + kCsvMarker.size()));
  } else {
    std::error_code ignored;
    std::filesystem::remove(csv, ignored);
  }
  try {
    const granular::Scene loaded = granular::loadScene(scene);
    (void)loaded;
  } catch (const granular::SceneError&) {
  } catch (const granular::ConfigError&) {
  }
  return 0;
}
