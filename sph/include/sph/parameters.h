#pragma once
/// @file
/// The plain parameter structs of the SPH library (defaults as LS-DYNA's *CONTROL_SPH).

#include <sph/kernels.h>

namespace sph
{
  /// Particle approximation, numbered as LS-DYNA's FORM.
  enum class Formulation
  {
    updated_lagrangian           = 0, ///< FORM 0: updated Lagrangian, plain kernel gradients
    updated_lagrangian_corrected = 1, ///< FORM 1: updated Lagrangian, renormalised gradients
    total_lagrangian             = 7, ///< FORM 7: total Lagrangian, plain kernel gradients
    total_lagrangian_corrected   = 8  ///< FORM 8: total Lagrangian, renormalised gradients
  };

  /// Rock constitutive model.
  enum class RockModel
  {
    elastic,             ///< linear isotropic elasticity
    mohr_coulomb,        ///< Mohr-Coulomb, non-associated (as *MAT_MOHR_COULOMB), softening
    mohr_coulomb_cutoff, ///< the same with a Rankine tension cut-off at `tensile_strength`
    hoek_brown           ///< generalised Hoek-Brown with its own tension cut-off, softening
  };

  /// SPH numerics.
  struct Parameters
  {
    double      spacing     = 2.5e-3; ///< lattice spacing dx [m]
    Formulation form        = Formulation::total_lagrangian_corrected; ///< LS-DYNA FORM
    double      cslh        = 1.2;    ///< smoothing length h = cslh * dx [-]; support radius 2h
    double      tssfac      = 0.9;    ///< dt = tssfac * min h/(c + |v|) [-]
    KernelType  kernel      = KernelType::cubic_spline; ///< smoothing kernel
    bool        evolve_h    = false;  ///< dh/dt = (h/dim) div v (updated Lagrangian only)
    double      av_alpha    = 1.0;    ///< Monaghan artificial viscosity, linear term [-]
    double      av_beta     = 1.0;    ///< Monaghan artificial viscosity, quadratic term [-]
    double      hourglass   = 0.1;    ///< Ganzenmueller hourglass coefficient (FORM 7, 8) [-]
    int         n_threads   = 0;      ///< OpenMP threads; 0 = omp_get_max_threads()
    /// Work units the threads take one at a time (each pass over the particles is cut into
    /// `chunks` ranges of equal work); 0 = automatic: one per 128 particles, 1 to 16. The
    /// results depend on it by round-off (the order of the sums), not on the thread count.
    int         chunks      = 0;
    /// 3-D pair forces four at a time with AVX2 where the CPU has it (false: the portable scalar
    /// loop; the two differ by round-off only)
    bool        vectorised  = true;
    /// With `vectorised`: the pair force in mixed precision, eight pairs at a time (differences
    /// of positions and the sums in double, the rest in float; src/pair_kernel_mixed.h). Used at
    /// spacings of 0.1 mm and more (finer ones keep double: |grad W|^2 would overflow a float)
    bool        single_precision = true;
  };

  /// Rock material. Strengths are positive numbers; stress in code is tension-positive.
  struct MaterialParameters
  {
    RockModel model             = RockModel::mohr_coulomb; ///< constitutive model
    double    density           = 2900.0;  ///< initial density rho_0 [kg/m^3]
    double    youngs_modulus    = 97.07e9; ///< E [Pa]
    double    poissons_ratio    = 0.28;    ///< nu [-]
    double    cohesion          = 32.99e6; ///< c [Pa] (Mohr-Coulomb)
    double    friction_angle    = 1.1114;  ///< phi [rad] (63.68 deg)
    double    dilation_angle    = 0.0;     ///< psi [rad]; psi < phi is non-associated flow
    double    tensile_strength  = 0.0;     ///< Rankine cut-off sigma_t [Pa] (mohr_coulomb_cutoff)
    double    hb_sigma_ci       = 282e6;   ///< Hoek-Brown intact UCS sigma_ci [Pa]
    double    hb_mb             = 25.0;    ///< Hoek-Brown m_b (= m_i for intact rock) [-]
    double    hb_s              = 1.0;     ///< Hoek-Brown s [-]
    double    hb_a              = 0.5;     ///< Hoek-Brown a [-]
    double    softening_strain  = 0.0;     ///< equivalent plastic strain to residual [-]; 0 = none
    double    residual_fraction = 0.1;     ///< residual strength / peak strength [-]
    /// Mohr-Coulomb friction angle of the fully damaged (crushed) rock phi_r [rad]: the angle
    /// goes linearly from phi to phi_r with the damage, as the cohesion goes to its residual.
    /// < 0: phi throughout (no friction softening).
    double    residual_friction_angle = -1.0;
    /// Crack closure (toe) elasticity, sph/crack_closure.h: Young's modulus at zero compressive
    /// stress E0 over E [-], in (0, 1]; 1 = none (linear elasticity).
    double    closure_modulus_ratio = 1.0;
    /// Crack closure stress sigma_cc [Pa] over which the modulus rises from E0 to E (used when
    /// closure_modulus_ratio < 1).
    double    closure_stress = 20e6;
  };
} // namespace sph
