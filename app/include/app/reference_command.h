#pragma once
/// @file
/// `cosim reference`: the implicit axisymmetric FE reference of a UCS case
/// (coupling/reference_cylinder.h): load-displacement curve, peak and the stress profiles at half
/// the peak, into a result folder.

#include <string>
#include <vector>

namespace app
{
  /// `cosim reference CASE.prm [-o OUTDIR] [--interface bonded|free-slip] [--platens rigid|elastic]
  /// [--mesh N] [--degree 1|2] [--increments N] [--end-strain X] [--set "S/K=v"] [--force]
  /// [--quiet]` (arguments after the subcommand). Returns the exit status: 0 done, 2 bad input.
  int reference_main(const std::vector<std::string> &args);
  /// Help text of `cosim reference`.
  std::string reference_help();
} // namespace app
