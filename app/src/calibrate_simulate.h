#pragma once
/// @file
/// `cosim calibrate --simulate`: a Mohr-Coulomb rock's strength calibrated through the coupled
/// simulator to a measured UCS (calibrate_simulate.cc).

#include <string>
#include <vector>

namespace app
{
  /// True when the arguments ask for the simulated calibration (--simulate CASE).
  bool is_simulated_calibration(const std::vector<std::string> &args);
  /// `cosim calibrate --simulate CASE ...`. Returns the exit status (1: not converged).
  int calibrate_simulate_main(const std::vector<std::string> &args);
} // namespace app
