// The coupled laboratory tests on body-fitted particles (SPH/Particle arrangement = body-fitted,
// sph/fitted_bodies.h): the elastic cylinder gives the rock's modulus as the lattice does, and the
// round disc splits from its centre along the loaded diameter.
#include "run_helpers.h"

#include <coupling/run_case.h>
#include <sph/fitted_bodies.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace coupling;
using namespace coupling::test;

namespace
{
  CaseParameters body_fitted(const std::string &test)
  {
    CaseParameters p;
    p.test                  = test;
    p.particle_arrangement  = sph::ParticleArrangement::body_fitted;
    p.rock.youngs_modulus   = 97.07e9; // group M1, Table 3
    p.rock.poissons_ratio   = 0.28;
    p.output.n_history_rows = 200;
    return p;
  }
} // namespace

TEST(CoupledBodyFitted, ElasticUcsGivesTheRockModulus)
{
  CaseParameters p     = body_fitted("UCS");
  p.rock.model         = sph::RockModel::elastic;
  p.sph.spacing        = 5e-3; // D/10, the coarsest the case files accept (for time)
  p.loading.end_strain = 1e-3;
  Keep rows;
  const Summary s = run_case(p, rows);
  ASSERT_GT(rows.rows.size(), 50u);
  // the run is on the rings: their count, not the lattice's
  EXPECT_EQ(s.n_particles, sph::make_fitted_cylinder(p.diameter, p.length, p.sph.spacing).positions.size());
  // the secant modulus from the gauges (middle half of the specimen) is E of the closed form
  // sigma = E eps. 2 %: the requirement; the corrected gradients (FORM 8) are exact for the
  // uniform field on any particle set, what remains is the explicit loading's dynamics
  EXPECT_NEAR(s.youngs_modulus / 97.07e9, 1.0, 0.02);
  // nu from the outer ring at mid-height: 5 % at D/10, where the ring's radial strain is read
  // from 10 rings (the lattice test asks 3 % at D/20)
  EXPECT_NEAR(s.poissons_ratio / 0.28, 1.0, 0.05);
  // energy and the two load cells: the lattice test's bounds (5 %: central differences' shadow
  // energy and the hourglass and viscous work; 0.1: twice the quasi-static limit)
  EXPECT_LT(s.energy_balance_error, 0.05);
  EXPECT_LT(s.max_force_imbalance, 0.1);
}

TEST(CoupledBodyFitted, RoundDiscSplitsFromTheCentreAlongTheLoadedDiameter)
{
  // group M1 with Table 4's c and phi (the BTS case's defaults), softening after the peak
  CaseParameters p       = body_fitted("BTS");
  p.length               = 0.025; // disc thickness, as cases/bts
  p.rock.model           = sph::RockModel::mohr_coulomb;
  p.rock.cohesion        = 32.99e6;
  p.rock.friction_angle  = 63.68 * 3.14159265358979323846 / 180.0; // [rad]
  p.sph.spacing          = 2.5e-3;
  p.loading.end_strain   = 0.004;
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  EXPECT_EQ(s.stop_reason, "post-peak drop");
  // the first damage near the centre (0.3 R: three ring spacings), a band along the loaded
  // diameter (spread along the load over the spread across > 3; diffuse failure: about 1):
  // the lattice disc's bounds (CoupledBts.CrackStartsAtTheCentreAndRunsAlongTheLoadedDiameter)
  EXPECT_LT(extra(s, "failure_onset_radius_ratio"), 0.3);
  EXPECT_GT(extra(s, "crack_alignment"), 3.0);
  EXPECT_LT(extra(s, "failure_onset_stress_MPa") * 1e6, s.peak_stress);
  // The strength: Mohr-Coulomb with these c, phi fails under the disc centre's plane stress
  // state (T across, -3T along the load) at T = UCS BTS_MC / (UCS + 3 BTS_MC) = 13.26 MPa, the
  // value the refined lattice disc converges to (13.52 at 1.25 mm, 13.56 at 1 mm). PLACEHOLDER
  const double ucs = 2 * p.rock.cohesion * std::cos(p.rock.friction_angle) / (1 - std::sin(p.rock.friction_angle));
  const double bts = 2 * p.rock.cohesion * std::cos(p.rock.friction_angle) / (1 + std::sin(p.rock.friction_angle));
  const double centre_state = ucs * bts / (ucs + 3 * bts);
  EXPECT_GT(s.peak_stress / centre_state, 0.95);
  EXPECT_LT(s.peak_stress / centre_state, 1.15);
}
