#pragma once
/// @file
/// Closed-form references the drivers and the studies compare with: rock strength (Mohr-Coulomb),
/// indentation (Sneddon's cone, Boussinesq's flat punch, Johnson's expanding cavity) and disc
/// cutting (the CSM estimate). Pure functions of their arguments; SI units, compression positive.

namespace coupling
{
  /// Mohr-Coulomb axial strength at confinement `sigma3` [Pa] for cohesion `c` [Pa] and friction
  /// angle `phi_deg` [deg], compression positive: 2c cos(phi)/(1 - sin(phi)) + sigma3 (1 +
  /// sin(phi))/(1 - sin(phi)).
  double mohr_coulomb_axial_strength(double c, double phi_deg, double sigma3);

  /// The CSM (Colorado School of Mines) estimate for a CCS disc cutter (Rostami 1997).
  struct CsmEstimate
  {
    double contact_angle = 0; ///< phi = acos((R - p) / R) [rad]
    double base_pressure = 0; ///< P0 in the crushed zone [Pa]
    double total         = 0; ///< resultant F_t [N]
    double normal        = 0; ///< F_n = F_t cos(phi / 2) [N]
    double rolling       = 0; ///< F_r = F_t sin(phi / 2) [N]
  };

  /// CSM: P0 = C (S sigma_c^2 sigma_t / (phi sqrt(R T)))^(1/3), C = 2.12, F_t = P0 phi R T /
  /// (1 + psi). ucs, bts [Pa]; radius R, tip width T, penetration p, line spacing S [m]; psi the
  /// pressure-distribution exponent [-] (0.2 for a CCS tip of 12-13 mm).
  CsmEstimate csm_cutter_force(double ucs, double bts, double radius, double tip_width,
                               double penetration, double spacing, double psi = 0.2);

  /// Sneddon: force [N] of a rigid cone of half-angle alpha [rad] at depth h [m] in an elastic
  /// half-space (E [Pa], nu): F = 2/pi E/(1 - nu^2) tan(alpha) h^2.
  double sneddon_cone_force(double youngs, double nu, double half_angle, double depth);

  /// Boussinesq: force [N] of a rigid flat cylindrical punch of radius a [m] at depth h [m] in an
  /// elastic half-space: F = 2 a E/(1 - nu^2) h.
  double flat_punch_force(double youngs, double nu, double radius, double depth);

  /// Johnson's expanding-cavity model: mean contact pressure [Pa] under a sharp indenter of
  /// half-angle alpha [rad] in an elastic-perfectly-plastic solid of yield stress Y [Pa]:
  /// p_m = 2/3 Y (1 + ln(E cot(alpha) / (3 Y))), E [Pa] (Young's modulus of the solid); the
  /// logarithm is taken as 0 where its argument is below 1 (a blunt indenter: no plastic zone
  /// beyond the core).
  double cavity_expansion_pressure(double youngs, double yield, double half_angle);
} // namespace coupling
