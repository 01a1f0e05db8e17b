#pragma once
/// @file
/// `cosim run`: read and check a case, run it, write the result folder atomically.

#include <string>
#include <vector>

namespace coupling
{
  /// `cosim run CASE.prm [-o OUTDIR] [--set "Section/Key=value" ...] [--force] [--quiet]`
  /// (arguments after the subcommand). Returns the exit status: 0 done, 2 bad input,
  /// 3 unstable run, 1 other failure.
  int run_main(const std::vector<std::string> &args);
  /// Help text of `cosim run`.
  std::string run_help();
} // namespace coupling
