#pragma once
/// Which --out folders `granular paper` writes into: new, empty, or a paper run's, recognised by
/// the files a paper run writes into its case folders, never by the folders' names alone.
#include <filesystem>

namespace granular::app {

/// Whether `dir` holds a paper run: one of the paper's case folders (mu0/, mu03/) holds the
/// case.txt that a run writes before its stage 1 (naming its scene), or a settled.ckpt.
bool isPaperRunFolder(const std::filesystem::path& dir);

/// Throws ConfigError, naming the folder and what to do, when `dir` exists, is not empty and is
/// not a paper run: its report.md and figures/ would be overwritten. IoError when it is a file.
/// `force` skips the check.
void checkPaperOutputFolder(const std::filesystem::path& dir, bool force);

}  // namespace granular::app
