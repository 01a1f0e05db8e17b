#pragma once
/// @file
/// `cosim calibrate`: Mohr-Coulomb c, phi back-calculated from UCS and BTS (Eqs. 14-15).

#include <string>
#include <vector>

namespace app
{
  /// `cosim calibrate` (arguments after the subcommand). Returns the exit status.
  int calibrate_main(const std::vector<std::string> &args);
  /// Help text of `cosim calibrate`.
  std::string calibrate_help();
} // namespace app
