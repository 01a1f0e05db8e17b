#pragma once
/// @file
/// Where the program finds what it ships: the measured-data tables and the plot scripts. Both are
/// found relative to the executable (`<prefix>/bin/cosim` -> `<prefix>/share/cosim/...`), the same
/// in a build tree and in an installed tree, never through the source tree. The environment
/// variables COSIM_DATA_DIR and COSIM_SCRIPT_DIR override them.

#include <filesystem>
#include <string>

namespace app
{
  /// The running executable's own path (/proc/self/exe).
  std::filesystem::path executable_path();

  /// `<prefix>/share/cosim` for the running executable at `<prefix>/bin/...`.
  std::filesystem::path share_directory();

  /// The measured-data folder (Tables 1-4 as CSV): $COSIM_DATA_DIR, else share_directory()/data.
  std::filesystem::path data_directory();

  /// The plot scripts' folder: $COSIM_SCRIPT_DIR, else share_directory()/scripts.
  std::filesystem::path script_directory();

  /// The program's version, "MAJOR.MINOR.PATCH" (CMake's project version).
  std::string version();

  /// The source commit it was built from ("unknown" outside a git checkout).
  std::string commit();
} // namespace app
