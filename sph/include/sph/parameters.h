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

  /// How the particles of a laboratory specimen (UCS / CTCS cylinder, BTS disc) are arranged.
  enum class ParticleArrangement
  {
    /// cell centres of a cubic lattice inside the body (sph/lattice.h): flat faces exact, a
    /// round surface a staircase
    lattice,
    /// layers of concentric rings (sph/fitted_bodies.h): the outer ring half a ring spacing
    /// inside the true round surface at every angle, volumes the annuli's shares
    body_fitted
  };

  /// Rock constitutive model.
  enum class RockModel
  {
    elastic,             ///< linear isotropic elasticity
    mohr_coulomb,        ///< Mohr-Coulomb, non-associated (as *MAT_MOHR_COULOMB), softening
    mohr_coulomb_cutoff, ///< the same with a Rankine tension cut-off at `tensile_strength`
    hoek_brown           ///< generalised Hoek-Brown with its own tension cut-off, softening
  };

  /// How the rock's strength softens after its peak (see rock_models.h, plastic_update).
  enum class SofteningLaw
  {
    /// linearly in the equivalent plastic strain, to the residual at `softening_strain`: the
    /// dissipated energy per unit crack area scales with the particle spacing
    strain,
    /// crack band: each particle dissipates `fracture_energy` (tensile failure) or
    /// `fracture_energy * shear_fracture_energy_ratio` (shear failure) per unit crack area over
    /// its band width (rock::crack_band_width: two spacings at CSLH 1.2), whatever the spacing
    fracture_energy
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
    /// No hourglass control across cracks (TL forms): a pair loses its hourglass force once
    /// either particle has begun to soften in tension (MaterialState::cracked), so that no
    /// hourglass force bridges an opening crack or works in its band; particles that soften in
    /// shear or crushing still carry load and keep it (src/body.cc, fade_hourglass)
    bool        hourglass_fade = true;
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
    SofteningLaw softening_law  = SofteningLaw::strain; ///< how the strength softens
    /// Mode I fracture energy G_I [J/m^2] (SofteningLaw::fracture_energy). 100 J/m^2: basalt's
    /// mode I toughness K_Ic = 2.7-3.8 MPa m^1/2 (Icelandic basalt; Balme et al. 2004, J.
    /// Volcanol. Geotherm. Res. 132, 159-172) gives G_I = K_Ic^2 (1 - nu^2) / E = 69-137 J/m^2
    /// at E = 97 GPa, nu = 0.28.
    double    fracture_energy   = 100.0;
    /// G_II / G_I [-]: shear (mode II) fracture energy over the mode I one. 6.25 = 2.5^2: rock's
    /// K_IIc is 2-3 times its K_Ic (Rao 1999, "Pure shear fracture of brittle rock", Lulea
    /// University of Technology; Backers et al. 2002, Int. J. Rock Mech. Min. Sci. 39, 755-769)
    /// and G = K^2 (1 - nu^2) / E in both modes.
    double    shear_fracture_energy_ratio = 6.25;
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
