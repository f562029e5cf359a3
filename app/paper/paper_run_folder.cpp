/// Recognising a `granular paper` run folder (paper_run_folder.hpp).
#include "paper_run_folder.hpp"

#include "csv_input.hpp"
#include "granular/error.hpp"
#include "paper_reference.hpp"

namespace granular::app {
namespace {

/// A case folder as a paper run leaves it: case.txt with the scene it ran, or (runs before
/// case.txt was written, or one stopped after settling) the settled checkpoint.
bool holdsPaperCase(const std::filesystem::path& caseDir) {
  std::error_code ec;
  if (std::filesystem::is_regular_file(caseDir / "settled.ckpt", ec)) return true;
  if (!std::filesystem::is_regular_file(caseDir / "case.txt", ec)) return false;
  try {
    return readKeyValues(caseDir / "case.txt").count("scene") > 0;
  } catch (const std::exception&) {
    return false;  // unreadable: not what a paper run wrote
  }
}

}  // namespace

bool isPaperRunFolder(const std::filesystem::path& dir) {
  for (const PaperReference& ref : kPaperCases) {
    if (holdsPaperCase(dir / ref.name)) return true;
  }
  return false;
}

void checkPaperOutputFolder(const std::filesystem::path& dir, bool force) {
  std::error_code ec;
  if (force || !std::filesystem::exists(dir, ec)) return;
  if (!std::filesystem::is_directory(dir, ec)) {
    throw IoError(dir.string() + ": --out must be a folder; this is a file");
  }
  if (std::filesystem::is_empty(dir, ec) || isPaperRunFolder(dir)) return;
  throw ConfigError(dir.string() +
                    ": not empty and not a `granular paper` run folder (no mu0/case.txt or "
                    "mu03/case.txt, which a paper run writes): its report.md and figures/ would "
                    "be overwritten; choose another --out (a new or empty folder) or add --force "
                    "to write into this one anyway");
}

}  // namespace granular::app
