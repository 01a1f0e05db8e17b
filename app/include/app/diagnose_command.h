#pragma once
/// @file
/// `cosim diagnose`: what the simulation gets wrong on measured data, the cause and the gain.

#include <string>
#include <vector>

namespace app
{
  /// `cosim diagnose` (arguments after the subcommand). Returns the exit status.
  int diagnose_main(const std::vector<std::string> &args);
  /// Help text of `cosim diagnose`.
  std::string diagnose_help();
} // namespace app
