#pragma once
/// @file
/// Back-calculation of Mohr-Coulomb c and phi from UCS and BTS (Yang et al. 2022, Eqs. 14-15):
/// UCS = 2c cos(phi)/(1 - sin(phi)), BTS = 2c cos(phi)/(1 + sin(phi)), compression positive.

#include <string>
#include <vector>

namespace coupling
{
  /// A linear Mohr-Coulomb envelope.
  struct MohrCoulombStrength
  {
    double cohesion = 0;       ///< [same unit as the strengths it came from]
    double friction_angle = 0; ///< [deg]
  };

  /// c and phi with the given UCS and BTS. Precondition 0 < bts < ucs (std::invalid_argument else).
  /// sin(phi) = (UCS - BTS)/(UCS + BTS), c = UCS (1 - sin(phi)) / (2 cos(phi)).
  MohrCoulombStrength calibrate_mohr_coulomb(double ucs, double bts);

  /// Eq. 14: uniaxial compressive strength of an envelope [unit of cohesion].
  double mohr_coulomb_ucs(const MohrCoulombStrength &strength);
  /// Eq. 15: tensile strength (BTS) of an envelope [unit of cohesion].
  double mohr_coulomb_bts(const MohrCoulombStrength &strength);

  /// `cosim calibrate` (arguments after the subcommand). Returns the exit status.
  int calibrate_main(const std::vector<std::string> &args);
  /// Help text of `cosim calibrate`.
  std::string calibrate_help();
} // namespace coupling
