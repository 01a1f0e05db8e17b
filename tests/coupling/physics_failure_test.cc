// Where and how the coupled specimens fail: the BTS crack starts at the disc centre and runs
// along the loaded diameter (plane elasticity + Griffith: the paper's Section 5.2, its Fig. 16),
// and a heterogeneous rock (Rock/Strength scatter) honours its per-particle strengths.
#include "run_helpers.h"

#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <stdexcept>

using namespace coupling;
using namespace coupling::test;

namespace
{
  // group M1 with Table 4's c and phi (the cases' defaults), softening after the peak
  CaseParameters m1(const std::string &test)
  {
    CaseParameters p;
    p.test                  = test;
    p.rock.model            = sph::RockModel::mohr_coulomb;
    p.rock.youngs_modulus   = 97.07e9;
    p.rock.poissons_ratio   = 0.28;
    p.rock.cohesion         = 32.99e6;
    p.rock.friction_angle   = 63.68 * 3.14159265358979323846 / 180.0; // [rad]
    p.output.n_history_rows = 200;
    return p;
  }

  /// `p` as the reference study's flattened disc (D 50 x 25 mm, flats of 20 deg) of body-fitted
  /// rings at spacing dx, loaded to a displacement of 0.4 % of D (cases/bts/bts-flattened.prm).
  CaseParameters flattened_fitted_disc(CaseParameters p, const double dx)
  {
    p.length               = 0.025;
    p.flat_angle           = 20 * M_PI / 180;
    p.particle_arrangement = sph::ParticleArrangement::body_fitted;
    p.sph.spacing          = dx;
    p.loading.end_strain   = 0.004;
    return p;
  }
} // namespace

TEST(CoupledBts, CrackStartsAtTheCentreAndRunsAlongTheLoadedDiameter)
{
  CaseParameters p     = m1("BTS");
  p.length             = 0.025; // disc thickness, as cases/bts
  p.sph.spacing        = 2.5e-3;
  p.loading.end_strain = 0.004;
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  // the first damaged particles lie near the centre: 0.3 of the radius is three particle
  // spacings at 2.5 mm (the run gives 0.10); damage starting under a platen would give about 0.9
  EXPECT_LT(extra(s, "failure_onset_radius_ratio"), 0.3);
  // the failed particles form a band along the loaded diameter: the spread along the load is
  // several times the spread across (6.0 at 2.5 mm); a diffuse or contact-crushing failure
  // gives about 1
  EXPECT_GT(extra(s, "crack_alignment"), 3.0);
  // and the damage starts before the peak: the crack opens, then the disc splits
  EXPECT_LT(extra(s, "failure_onset_stress_MPa") * 1e6, s.peak_stress);
  EXPECT_EQ(s.stop_reason, "post-peak drop");
}

TEST(CoupledBts, ADiameterThatTheSpacingDoesNotDivideStartsClearOfThePlatens)
{
  // 50 mm / 2.2 mm = 22.7: the disc has 23 cells across, its outer particles reach 0.3 mm past
  // the nominal diameter, and flat platens at 0 and D started pressed into them (the run stopped
  // as unstable at step 1, 315 m/s). The platens now start where the outermost particles touch.
  CaseParameters p     = m1("BTS");
  p.length             = 0.025;
  p.sph.spacing        = 2.2e-3;
  p.loading.end_strain = 0.004;
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  EXPECT_EQ(s.stop_reason, "post-peak drop");
  // between the converged 13.5 MPa (1 and 1.25 mm: 13.56, 13.52) and the 2.5 mm value 14.98,
  // with a margin of half a MPa each way for the lattice's different facets (2.2 mm: 13.99)
  EXPECT_GT(s.peak_stress, 13.0e6);
  EXPECT_LT(s.peak_stress, 15.5e6);
}

// The flattened Brazilian disc (Test/Flat loading angle = 20 deg, the reference study's disc):
// flats of a fixed width at any spacing, and the split starts at the centre. Its first damage
// is where Mohr-Coulomb first fails under the centre's state. For a load spread over an arc
// 2 alpha (Hondros), the centre sees tension T (sin 2a - a)/a and compression T (sin 2a + a)/a,
// T = 2P/(pi D t). So failure needs T = UCS / ((sin 2a + a)/a + k (sin 2a - a)/a), with
// k = (1 + sin phi)/(1 - sin phi). That is 13.76 MPa for M1 at 20 deg, against 13.26 MPa under
// a line load.
TEST(CoupledBts, FlattenedDiscSplitsFromItsCentreWhereMohrCoulombSays)
{
  CaseParameters p     = m1("BTS");
  p.length             = 0.025;
  p.flat_angle         = 20 * M_PI / 180;
  p.sph.spacing        = 1.25e-3;
  p.loading.end_strain = 0.004;
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  const double  a = 0.5 * p.flat_angle, sphi = std::sin(p.rock.friction_angle);
  const double  k = (1 + sphi) / (1 - sphi);
  const double  ucs = 2 * p.rock.cohesion * std::sqrt(k);
  const double  onset_closed =
    ucs / ((std::sin(2 * a) + a) / a + k * (std::sin(2 * a) - a) / a);
  std::printf("flattened disc: onset %.3f MPa at r/R %.3f (closed form %.3f MPa), peak %.3f MPa\n",
              extra(s, "failure_onset_stress_MPa"), extra(s, "failure_onset_radius_ratio"),
              onset_closed * 1e-6, s.peak_stress * 1e-6);
  // measured r/R 0.05 (0.07 at 2.5 mm, 0.06 at 1 mm); a centre split is taken as one within
  // 0.2 of the radius (at 0.8 mm the flats' edges fail first, r/R 0.98)
  EXPECT_LT(extra(s, "failure_onset_radius_ratio"), 0.2);
  // measured +2.0 % at 1.25 mm, +0.2 % at 1 mm (+18 % at 2.5 mm, 3.5 particles on a flat): 3 %
  // holds the 1.25 mm value; the line-load value is 3.6 % below the closed form, so a flat that
  // carried no spread load would fail it
  EXPECT_NEAR(extra(s, "failure_onset_stress_MPa") * 1e6 / onset_closed, 1.0, 0.03);
  EXPECT_GT(extra(s, "crack_alignment"), 3.0); // measured 4.3
  EXPECT_EQ(s.stop_reason, "post-peak drop");
}

// The same flattened disc built of rings pulled onto its flats (SPH/Particle arrangement =
// body-fitted): the platens press the true flats at every spacing, and the elastic field is
// Hondros's (CoupledBodyFitted.ElasticFlattenedDiscCarriesItsFlatsLoadAsHondrosSays; the lattice
// disc above is 12 % low in the centre's tension at 1.25 mm, which is why its onset sits on the
// plane closed form). The Mohr-Coulomb disc's peak converges from the case's 2.5 mm on: 12.60 /
// 12.72 / 12.77 / 12.67 MPa at 2.5 / 1.25 / 1 / 0.8 mm, because the outer ring's particles tile
// each flat exactly (with the ring's even spacing three particles covered 82 % of the flat at 2.5
// mm and the peak was 11.80, 7.2 % low). It is 8 % below the plane closed form (13.76 MPa)
// because the 25 mm thick disc's faces carry 1.3 times its mid-plane's tension (elastic, 1 mm),
// and the first damage is at the flats' corners (r/R 1), where a rigid flat punch's pressure
// is singular.
TEST(CoupledBts, FlattenedBodyFittedDiscConvergesInSpacing)
{
  std::array<Summary, 3> s;
  const std::array<double, 3> spacing{2.5e-3, 1.25e-3, 1e-3};
  for (std::size_t k = 0; k < s.size(); ++k)
    {
      RunObserver quiet;
      s[k] = run_case(flattened_fitted_disc(m1("BTS"), spacing[k]), quiet);
      std::printf("dx %g: peak %.4f MPa, alignment %.2f\n", spacing[k], s[k].peak_stress / 1e6,
                  extra(s[k], "crack_alignment"));
      EXPECT_EQ(s[k].stop_reason, "post-peak drop");
      // the split runs along the loaded diameter: measured alignment 6.8 / 5.2 / 6.0
      EXPECT_GT(extra(s[k], "crack_alignment"), 3.0);
    }
  // the two finest the suite can afford: 1 %, the bound asked of a converged strength
  // (measured 0.39 %; the lattice disc's flattened peaks move 2.7 % between them); all three
  // within 2 % of each other, the bound asked of a BTS from 2.5 mm on (measured 1.3 %; with
  // the ring's even spacing on the flats 2.5 mm was 7.2 % low)
  EXPECT_NEAR(s[2].peak_stress / s[1].peak_stress, 1.0, 0.01);
  for (std::size_t k = 0; k < s.size(); ++k)
    for (std::size_t j = 0; j < k; ++j)
      EXPECT_NEAR(s[k].peak_stress / s[j].peak_stress, 1.0, 0.02) << spacing[j] << " " << spacing[k];
}

// A Hoek-Brown rock with a tension cut-off on the same flattened body-fitted disc: group M10's
// envelope (Rock/Strength parameters = envelope: sigma_ci 206.1 MPa, m_b 10.02, a 0.744) with the
// cut-off that cosim calibrate --cutoff-from found for Table 3's BTS on this disc at 1.25 mm
// (6.9618 MPa). Its peak converges (measured 7.98 / 7.99 MPa at 1.25 / 1 mm; 7.77 at 2.5 mm, 2.7 %
// low, as M8 and M9 are 3.5 / 3.4 %; on the round lattice disc the same rock gives 12.9-13.3 MPa,
// its peak hardly following the cut-off), so the calibrated cut-off is the rock's, not the
// spacing's.
TEST(CoupledBts, CutOffRockOnTheFlattenedBodyFittedDiscConverges)
{
  std::array<Summary, 2> s;
  const std::array<double, 2> spacing{1e-3, 1.25e-3};
  for (std::size_t k = 0; k < 2; ++k)
    {
      CaseParameters p        = flattened_fitted_disc(m1("BTS"), spacing[k]);
      p.rock.model            = sph::RockModel::hoek_brown;
      p.rock.youngs_modulus   = 74.76e9; // group M10, Table 3
      p.rock.poissons_ratio   = 0.22;
      p.rock.hb_sigma_ci      = 206.1e6;
      p.rock.hb_mb            = 10.023906686963763;
      p.rock.hb_a             = 0.7443428743848444;
      p.rock.tensile_strength = 6.9618e6;
      RunObserver quiet;
      s[k] = run_case(p, quiet);
      std::printf("dx %g: peak %.4f MPa, alignment %.2f, shear %g, tensile %g\n", spacing[k],
                  s[k].peak_stress / 1e6, extra(s[k], "crack_alignment"),
                  extra(s[k], "failure_mode_shear"), extra(s[k], "failure_mode_tensile"));
      EXPECT_EQ(s[k].stop_reason, "post-peak drop");
      EXPECT_GT(extra(s[k], "crack_alignment"), 3.0); // measured 10.7 / 8.9
      // a tensile split: the cut-off, no shear failure
      EXPECT_EQ(extra(s[k], "failure_mode_shear"), 0.0);
    }
  // 2 %: the spacing's effect asked of a converged strength (measured 0.15 %); and at 1.25 mm
  // Table 3's 7.99 MPa, the calibration's target, within its 0.5 % tolerance
  EXPECT_NEAR(s[0].peak_stress / s[1].peak_stress, 1.0, 0.02);
  EXPECT_NEAR(s[1].peak_stress / 7.99e6, 1.0, 0.005);
}

TEST(CoupledUcs, StrengthScatterIsHonouredAndWeakensTheSpecimen)
{
  CaseParameters p     = m1("UCS");
  p.sph.spacing        = 5e-3; // coarse, for time
  p.loading.end_strain = 0.006;
  RunObserver quiet;
  const Summary homogeneous = run_case(p, quiet);
  // a Weibull modulus of 1000 scatters the strength by 0.13 %: the peak must be the homogeneous
  // one within 0.5 % (a scatter read but not applied would pass this, the next one not)
  p.rock_case.strength_scatter = 1000;
  const Summary narrow    = run_case(p, quiet);
  EXPECT_NEAR(narrow.peak_stress / homogeneous.peak_stress, 1.0, 0.005);
  // m = 5 (coefficient of variation 23 %): weak particles yield early, soften and load their
  // neighbours; the specimen fails below the homogeneous strength (at 2.5 mm: -27 %, m = 10: -22 %)
  p.rock_case.strength_scatter = 5;
  const Summary scattered = run_case(p, quiet);
  EXPECT_LT(scattered.peak_stress, 0.9 * homogeneous.peak_stress);
  // and damage starts well below the peak, in the weakest particles, not at the peak as in the
  // homogeneous rock
  EXPECT_LT(extra(scattered, "failure_onset_stress_MPa") * 1e6, 0.8 * scattered.peak_stress);
  // another seed is another rock of the same statistics: the peak moves, but by less than the
  // scatter's own effect
  p.rock_case.scatter_seed  = 2;
  const Summary other  = run_case(p, quiet);
  EXPECT_NE(other.peak_stress, scattered.peak_stress);
  EXPECT_NEAR(other.peak_stress / scattered.peak_stress, 1.0, 0.1);
}

// A heterogeneous rock (Weibull m = 10 on 5 mm cells, crack-band softening, Table 4's c, phi)
// fails through its weak cells, not everywhere at once as the homogeneous cylinder does, and held
// ends then confine it: Coulomb friction raises the mean peak (the homogeneous one's falls,
// CoupledKinematic.EndFrictionLiesBetweenFreeSlipAndBondedEnds), and a short specimen with
// friction is stronger than a long one. (With the c, phi calibrated to Table 3 through the
// simulator the same rocks are weakened by 4.7 % at 2.5 mm: cases/studies/platens/README.md.)
TEST(CoupledUcs, EndFrictionStrengthensAHeterogeneousRock)
{
  CaseParameters p                = m1("UCS");
  p.sph.spacing                   = 5e-3; // coarse, for time (2.5 mm: cases/studies/platens)
  p.loading.end_strain            = 0.006;
  p.rock.softening_law            = sph::SofteningLaw::fracture_energy;
  p.rock_case.strength_scatter    = 10;
  p.rock_case.scatter_length      = 5e-3;
  RunObserver quiet;
  double free_mean = 0, held_mean = 0, short_mean = 0;
  for (const int seed : {1, 2, 3})
  {
    p.rock_case.scatter_seed = seed;
    p.length                 = 0.1;
    p.platens.friction       = 0;
    const double free_slip   = run_case(p, quiet).peak_stress;
    p.platens.friction       = 0.3;
    const double held        = run_case(p, quiet).peak_stress;
    p.length                 = 0.05;
    const double held_short  = run_case(p, quiet).peak_stress;
    free_mean += free_slip / 3;
    held_mean += held / 3;
    short_mean += held_short / 3;
    std::printf("seed %d: free slip %.2f, mu 0.3 %.2f, mu 0.3 at L/D 1 %.2f MPa\n", seed, free_slip * 1e-6,
                held * 1e-6, held_short * 1e-6);
    // no rock is weakened as the homogeneous one is (-9.2 % at 5 mm); measured 1.086 / 1.025 /
    // 0.988 (2.5 mm, unfaded: 1.083 / 1.070 / 0.996): one rock may lose a little, 2.5 % allows
    // twice it
    EXPECT_GT(held / free_slip, 0.975) << "seed " << seed;
  }
  // the mean over three rocks: measured +3.2 % (2.5 mm, unfaded: +4.9 %; Siebel's
  // 1 + mu D / (3 L) is +5 %); 1.5 % is half of it, clear of no effect and far from the
  // homogeneous -9.2 %
  EXPECT_GT(held_mean / free_mean, 1.015);
  EXPECT_LT(held_mean / free_mean, 1.2);
  // measured 202.4 against 191.9 MPa (2.5 mm, unfaded: 194.8 against 187.3)
  EXPECT_GT(short_mean, held_mean);
}

// A ductile heterogeneous rock (crack band, characteristic length E G_I / f_t^2 = 2.7 m) in a
// short, wide specimen (L/D 1/2) between rigid platens with end friction 0.49: the rock of
// `cosim diagnose`'s end-friction fit at the far end of its range (the benchmark's group A).
// Its particles soften in shear and crushing under the held ends while they carry the load;
// with hourglass control dropped on every softening particle this run went unstable (step 977,
// |v| 2,745 m/s at the bottom rim, peak 188 MPa). Hourglass control is dropped across tensile
// cracks only (sph::Parameters::hourglass_fade), and the run stays stable, its kinetic energy
// about 1 % of its internal energy.
TEST(CoupledUcs, ADuctileHeterogeneousShortCylinderWithEndFrictionStaysStable)
{
  CaseParameters p              = m1("UCS");
  p.diameter                    = 0.07937;
  p.length                      = 0.03969;
  p.sph.spacing                 = 3.969e-3; // 20 cells across, as the fit ran it
  p.loading.end_strain          = 0.01;
  p.platens.friction            = 0.4921887;
  p.rock.model                  = sph::RockModel::mohr_coulomb_cutoff;
  p.rock.density                = 2700;
  p.rock.youngs_modulus         = 74.76e9;
  p.rock.poissons_ratio         = 0.22;
  p.rock.cohesion               = 31.45454e6;
  p.rock.friction_angle         = 49.30972 * M_PI / 180;
  p.rock.tensile_strength       = 9.080783e6;
  p.rock.softening_law          = sph::SofteningLaw::fracture_energy;
  p.rock.fracture_energy        = 2993.229;
  p.rock_case.strength_scatter  = 10;
  p.rock_case.scatter_length    = 5e-3;
  p.rock_case.scatter_seed      = 3;
  RunObserver quiet;
  Summary s;
  try
  {
    s = run_case(p, quiet);
  }
  catch (const std::exception &e)
  {
    FAIL() << e.what();
  }
  std::printf("peak %.2f MPa, kinetic / internal %.4f, %s\n", s.peak_stress * 1e-6,
              s.max_kinetic_to_internal_energy, s.stop_reason.c_str());
  // 0.05: five times the loading's own bound (Loading/Max kinetic ratio 0.01); measured 0.0107,
  // the post-peak drop included (the unstable run: 0.29 at its last history row)
  EXPECT_LT(s.max_kinetic_to_internal_energy, 0.05);
  // it carries load to a peak and past it (measured 226.0 MPa, the unfaded run 351.2): 150 MPa,
  // a third below the measured peak, tells that from a collapse at the first softening
  EXPECT_GT(s.peak_stress, 150e6);
}

// A heterogeneous disc (Weibull m = 10 on 5 mm cells fixed in space, crack-band softening) is
// the same rock at every spacing and converges: rock 1's BTS at 1.25 and 1 mm (measured 12.26 and
// 12.37 MPa, the worst of three rocks; the 2.5 mm disc is 9 % stronger). 2 %: the two finest
// spacings' agreement asked of the BTS; per-particle scatter draws another rock at each spacing.
TEST(CoupledBts, HeterogeneousDiscConvergesBetweenTheTwoFinestSpacings)
{
  CaseParameters p             = m1("BTS");
  p.length                     = 0.025; // disc thickness, as cases/bts
  p.loading.end_strain         = 0.004;
  p.rock.softening_law         = sph::SofteningLaw::fracture_energy;
  p.rock_case.strength_scatter = 10;
  p.rock_case.scatter_length   = 5e-3;
  p.rock_case.scatter_seed     = 1;
  RunObserver quiet;
  p.sph.spacing         = 1.25e-3;
  const Summary coarse  = run_case(p, quiet);
  p.sph.spacing         = 1e-3;
  const Summary fine    = run_case(p, quiet);
  std::printf("BTS %.3f MPa at 1.25 mm, %.3f MPa at 1 mm\n", coarse.peak_stress * 1e-6, fine.peak_stress * 1e-6);
  EXPECT_NEAR(fine.peak_stress / coarse.peak_stress, 1.0, 0.02);
  // and it splits along the loaded diameter at both (measured crack_alignment 3.7 and 3.9)
  EXPECT_GT(extra(coarse, "crack_alignment"), 2.5);
  EXPECT_GT(extra(fine, "crack_alignment"), 2.5);
}

namespace
{
  // Keeps the last particle snapshot of a run.
  struct LastSnapshot : RunObserver
  {
    ParticleSnapshot particles;
    void snapshot(double, const ParticleSnapshot &p, const std::vector<MeshSnapshot> &) override
    {
      particles = p;
    }
  };

  // particles per failure mode (0 none, 1 tensile, 2 shear, 3 crushed) of those for which
  // `where(x, z)` holds (x, z: reference position [m])
  template <typename Where>
  std::array<double, 4> mode_counts(const ParticleSnapshot &s, Where where)
  {
    std::array<double, 4> n{0, 0, 0, 0};
    for (std::size_t i = 0; i < s.n; ++i)
    {
      const double x = s.position[3 * i] - s.displacement[3 * i];
      const double z = s.position[3 * i + 2] - s.displacement[3 * i + 2];
      if (where(x, z))
        n[s.failure_mode[i]] += 1;
    }
    return n;
  }
} // namespace

TEST(CoupledFailureMode, UcsFailsInShearAndTheBtsSplitIsTensile)
{
  {
    // UCS, coarse: the cylinder yields under uniaxial compression, where the Mohr-Coulomb
    // failure plane is in compression (sigma_n = -sigma_c (1 - sin phi)/2 < 0): shear. Tension
    // appears only at the free surface's bulging edge; crushing (a mean compression of the full
    // UCS) nowhere, the platens being frictionless
    CaseParameters p     = m1("UCS");
    p.sph.spacing        = 5e-3;
    p.loading.end_strain = 0.006;
    LastSnapshot last;
    const Summary s = run_case(p, last);
    ASSERT_EQ(last.particles.failure_mode.size(), last.particles.n);
    const double tensile = extra(s, "failure_mode_tensile"), shear = extra(s, "failure_mode_shear"),
                 crushed = extra(s, "failure_mode_crushed");
    ASSERT_GT(tensile + shear + crushed, 0.0) << "the specimen must have failed";
    EXPECT_GT(shear / (tensile + shear + crushed), 0.8);
    // the summary's counts are those of the field
    const auto all = mode_counts(last.particles, [](double, double) { return true; });
    EXPECT_EQ(all[2], shear);
  }
  {
    // BTS at 2.5 mm: along the loaded diameter the disc centre is under (T, -3T), the failure
    // plane in tension for phi = 63.7 deg (sigma_n = T (-1 + 2 sin phi) > 0): the central split
    // is tensile. Near the platens (within 0.2 D) the contact compresses the rock: not counted.
    CaseParameters p     = m1("BTS");
    p.length             = 0.025;
    p.sph.spacing        = 2.5e-3;
    p.loading.end_strain = 0.004;
    LastSnapshot last;
    run_case(p, last);
    const double D      = 0.05;
    const auto central  = mode_counts(last.particles, [D](double x, double z) {
      return std::abs(x) < 0.1 * D && std::abs(z - 0.5 * D) < 0.3 * D;
    });
    const double failed = central[1] + central[2] + central[3];
    ASSERT_GT(failed, 0.0) << "the disc must have split";
    EXPECT_GT(central[1] / failed, 0.9);
  }
}
