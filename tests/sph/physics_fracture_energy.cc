// Crack band softening (Rock/Softening law = fracture energy): a bar pulled apart in direct
// tension dissipates the fracture energy per unit crack area, whatever the particle spacing.
#include <sph/body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>

namespace
{
  using namespace sph;

  /// What a direct tension test of a bar measured.
  struct TensionResult
  {
    double peak_stress    = 0; ///< largest end force / section [Pa]
    double final_stress   = 0; ///< end force / section at the end [Pa]
    double dissipated     = 0; ///< work of the end forces - elastic - kinetic energy left [J]
    double plastic        = 0; ///< the body's own plastic dissipation [J]
    double n_broken       = 0; ///< particles at damage 1
    double per_layer      = 0; ///< particles in one lattice layer across the bar
    double section        = 0; ///< cross-section of the bar [m^2]
  };

  // Rock with a Rankine cut-off at 10 MPa far below its Mohr-Coulomb tensile limit (c = 30 MPa,
  // phi = 45 deg: 2c cos(phi)/(1 + sin(phi)) = 35 MPa), softening to zero strength (residual 0)
  // by the crack band law with G_I = 100 J/m^2 (basalt's order): a tensile crack.
  MaterialParameters cut_off_rock()
  {
    MaterialParameters m;
    m.model             = RockModel::mohr_coulomb_cutoff;
    m.density           = 2900;
    m.youngs_modulus    = 60e9;
    m.poissons_ratio    = 0.25;
    m.cohesion          = 30e6;
    m.friction_angle    = M_PI / 4;
    m.tensile_strength  = 10e6;
    m.residual_fraction = 0;
    m.softening_law     = SofteningLaw::fracture_energy;
    m.fracture_energy   = 100;
    return m;
  }

  // A bar of section a x a and length L along z on a lattice of spacing dx, its end layers pulled
  // apart along z (the bottom layer held, the top one moved, the others free), the layer at
  // mid-length 2 % weaker so that the crack opens there and nowhere else. The pull speeds up
  // smoothly over 30 P-wave transits of the bar to a speed that would reach the cut-off stress
  // in another 15, then goes on until the ends have moved `opening` [m].
  TensionResult pull_apart(const MaterialParameters &m, const double dx, const double a,
                           const double L, const double opening, const bool fade = true)
  {
    Parameters prm; // the default hourglass control (0.1), dropped across the crack or not
    prm.spacing           = dx;
    prm.hourglass_fade    = fade;
    const Lattice<3> lat  = make_block<3>(Vector<3>(0, 0, 0), Vector<3>(a, a, L), dx);
    Body<3>          body(prm, m, lat.positions, lat.volumes);
    const unsigned   n    = body.n_particles();
    const auto      &x0   = body.reference_positions();
    std::vector<double> factor(n, 1.0);
    const double z_mid = 0.5 * L;
    for (unsigned i = 0; i < n; ++i)
      if (std::abs(x0[i][2] - (z_mid - 0.5 * dx)) < 0.25 * dx)
        factor[i] = 0.98;
    body.set_strength_factors(factor);
    const double c = body.wave_speed(), transit = L / c;
    const double t_ramp = 30 * transit;
    const double v_max  = m.tensile_strength / m.youngs_modulus * L / (15 * transit);
    TensionResult r;
    r.section   = a * a;
    r.per_layer = std::round(a / dx) * std::round(a / dx);
    double t = 0, moved = 0;
    while (moved < opening)
      {
        body.compute_forces();
        const double dt = body.stable_time_step();
        const double tm = t + 0.5 * dt;
        const double v  = tm < t_ramp ? v_max * 0.5 * (1 - std::cos(M_PI * tm / t_ramp)) : v_max;
        for (unsigned i = 0; i < n; ++i)
          {
            if (x0[i][2] < dx)
              body.constrain(i, 2, 0.0);
            else if (x0[i][2] > L - dx)
              body.constrain(i, 2, v);
          }
        body.integrate(dt);
        t += dt;
        moved += v * dt;
        double f = 0;
        for (unsigned i = 0; i < n; ++i)
          if (x0[i][2] > L - dx)
            f += body.reaction_force(i)[2];
        r.peak_stress  = std::max(r.peak_stress, f / r.section);
        r.final_stress = f / r.section;
      }
    const Energies e = body.energies();
    r.dissipated     = e.external - e.internal - e.kinetic;
    r.plastic        = e.plastic;
    for (unsigned i = 0; i < n; ++i)
      r.n_broken += body.damage(i) >= 1.0 ? 1.0 : 0.0;
    std::cout << "dx " << dx * 1e3 << " mm: peak " << r.peak_stress / 1e6 << " MPa, final "
              << r.final_stress / 1e6 << " MPa, dissipated " << r.dissipated / r.section
              << " J/m^2 (plastic " << e.plastic / r.section << ", viscous " << e.viscous / r.section
              << ", hourglass " << e.hourglass / r.section << "), broken particles " << r.n_broken
              << " (one layer: " << r.per_layer << ")" << std::endl;
    return r;
  }
} // namespace

TEST(SphCrackBand, DirectTensionDissipatesTheFractureEnergyAtTwoSpacings)
{
  const MaterialParameters m = cut_off_rock();
  // 10 x 10 x 20 mm at 2.5 and 1.25 mm. The band (sph::rock::crack_band_width: two layers)
  // opens fully at 2 G / f_t = 20 um, past which no more energy goes; pulled to 30 um. The bar
  // is shorter than 2 E G / f_t^2 = 120 mm, where its own elastic energy would make the
  // softening snap back.
  const double opening = 30e-6;
  const TensionResult coarse = pull_apart(m, 2.5e-3, 0.01, 0.02, opening);
  const TensionResult fine   = pull_apart(m, 1.25e-3, 0.01, 0.02, opening);
  for (const TensionResult *r : {&coarse, &fine})
    {
      // the bar broke: the force rose to the cut-off (1 % overshoot) and fell to nothing
      EXPECT_NEAR(r->peak_stress / m.tensile_strength, 1.0, 0.02);
      EXPECT_LT(std::abs(r->final_stress), 0.01 * m.tensile_strength);
      // one band's worth of particles broke: two layers (16 and 64 particles a layer)
      EXPECT_NEAR(r->n_broken / r->per_layer, 2.0, 0.01);
      // the energy the end forces put in and the bar did not keep (elastic, kinetic) per unit
      // crack area is G_I: 10 % for the viscous dissipation and the start of softening in the
      // layers beside the band (the runs give 3.5 and 3.6 % over; without hourglass control
      // 3.4 and 3.7 %)
      EXPECT_NEAR(r->dissipated / r->section / m.fracture_energy, 1.0, 0.10);
    }
  // and it does not move with the spacing: 5 % (the runs: 0.1 %); the strain law's energy
  // would halve with the spacing
  EXPECT_NEAR(fine.dissipated / coarse.dissipated, 1.0, 0.05);
}

TEST(SphCrackBand, UnfadedHourglassForcesBridgeTheCrack)
{
  // The same bar with hourglass forces between broken particles as between intact ones
  // (SPH/Hourglass fading = false): they hold the crack's faces together with a stiffness of
  // ~0.1 E, so the broken bar still carries load and the end forces do far more work than G_I.
  // Measured 2.9 MPa (29 % of the strength) and 1.56 G_I at 2.5 mm: the bounds (> 15 %, > 1.3
  // G_I) tell that state from the faded one's (0.07 %, 1.035 G_I) by wide margins
  const MaterialParameters m = cut_off_rock();
  const TensionResult      r = pull_apart(m, 2.5e-3, 0.01, 0.02, 30e-6, false);
  EXPECT_GT(r.final_stress, 0.15 * m.tensile_strength);
  EXPECT_GT(r.dissipated / r.section / m.fracture_energy, 1.3);
}
