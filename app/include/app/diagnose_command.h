#pragma once
/// @file
/// `cosim diagnose`: what the simulation gets wrong on measured data, the cause and the gain.

#include <diagnose/diagnose.h>

#include <string>
#include <vector>

namespace app
{
  /// `cosim diagnose` (arguments after the subcommand). Returns the exit status.
  int diagnose_main(const std::vector<std::string> &args);
  /// The reader of the coupled runs' cases in `cosim diagnose`: the case file `defaults` with the
  /// overrides, through the case-file reader (what runs is what `cosim run` would read); the text
  /// is the used-parameters file, naming no `defaults` path.
  diagnose::CaseReader case_reader(const std::string &defaults);
  /// Help text of `cosim diagnose`.
  std::string diagnose_help();
} // namespace app
