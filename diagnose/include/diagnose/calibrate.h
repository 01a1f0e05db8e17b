#pragma once
/// @file
/// Back-calculation of Mohr-Coulomb c and phi from UCS and BTS (Yang et al. 2022, Eqs. 14-15):
/// UCS = 2c cos(phi)/(1 - sin(phi)), BTS = 2c cos(phi)/(1 + sin(phi)), compression positive.
/// And a curved envelope through all of a group's strengths: generalised Hoek-Brown with a tension
/// cut-off, fitted to UCS, BTS and triaxial strengths together.

#include <vector>

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

  /// Generalised Hoek-Brown envelope of intact rock (s = 1) with a tension cut-off, compression
  /// positive: sigma1 = sigma3 + sigma_ci (m_b sigma3 / sigma_ci + 1)^a, and sigma3 >= -tensile.
  struct HoekBrownStrength
  {
    double sigma_ci = 0; ///< uniaxial compressive strength [unit of the strengths]
    double m_b      = 0; ///< [-]
    double a        = 0.5; ///< [-]
    double tensile  = 0; ///< cut-off [unit of the strengths]; <= 0: none
  };

  /// A measured triaxial strength: sigma1 at failure under confinement sigma3.
  struct TriaxialStrength
  {
    double sigma3 = 0, sigma1 = 0;
  };

  /// sigma1 on the envelope at sigma3 (without the cut-off) [unit of sigma_ci].
  double hoek_brown_sigma1(const HoekBrownStrength &strength, double sigma3);

  /// The Brazilian strength of the envelope: the load at which the disc centre's elastic state
  /// (compression 3 t, tension t) reaches the envelope or the cut-off, whichever comes first.
  double hoek_brown_disc_strength(const HoekBrownStrength &strength);

  /// The envelope through a group's strengths: sigma_ci = UCS (the uniaxial state exactly), the
  /// tension cut-off at the BTS, and
  /// - with two or more triaxial strengths: m_b and a (0.4 <= a <= 0.95) minimising the squared
  ///   relative misses of the triaxial strengths and of the BTS (the disc's strength,
  ///   hoek_brown_disc_strength) together;
  /// - with one: a = 1/2, m_b minimising the same misses;
  /// - with none: a = 1/2, m_b through the disc centre's state at failure (3 BTS, -BTS):
  ///   m_b = (UCS^2 - 16 BTS^2) / (UCS BTS).
  /// Throws std::invalid_argument unless 0 < 4 BTS < UCS and every sigma1 > sigma3 >= 0.
  HoekBrownStrength calibrate_hoek_brown(double ucs, double bts,
                                         const std::vector<TriaxialStrength> &triaxial);
} // namespace diagnose
