#pragma once
/// @file
/// Back-calculation of Mohr-Coulomb c and phi from UCS and BTS (Yang et al. 2022, Eqs. 14-15):
/// UCS = 2c cos(phi)/(1 - sin(phi)), BTS = 2c cos(phi)/(1 + sin(phi)), compression positive.

namespace diagnose
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

  /// The c, phi whose envelope holds the uniaxial state (UCS, 0) and the Brazilian disc centre's
  /// elastic stress state (compression 3 BTS, tension BTS; plane elasticity, Hondros) instead of
  /// uniaxial tension (BTS): N = (1 + sin phi)/(1 - sin phi) = UCS/BTS - 3, c = UCS / (2 sqrt N).
  /// A Mohr-Coulomb disc then splits at the measured BTS; with Eqs. 14-15 it splits at
  /// UCS BTS / (UCS + 3 BTS) (M1: 13.26 instead of 15.43 MPa). Throws std::invalid_argument
  /// unless UCS > 4 BTS > 0 (phi > 0).
  MohrCoulombStrength calibrate_mohr_coulomb_brazilian(double ucs, double bts);

  /// Eq. 14: uniaxial compressive strength of an envelope [unit of cohesion].
  double mohr_coulomb_ucs(const MohrCoulombStrength &strength);
  /// Eq. 15: tensile strength (BTS) of an envelope [unit of cohesion].
  double mohr_coulomb_bts(const MohrCoulombStrength &strength);
} // namespace diagnose
