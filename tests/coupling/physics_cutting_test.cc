// The indentation driver against closed forms: a rigid flat cylindrical punch pressed into an
// elastic rock block (Boussinesq), force balance between the cutter and the block's supports, and
// the CSM cutter-force estimate against hand-computed numbers.
#include "run_helpers.h"

#include <coupling/references.h>

#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace coupling;
using namespace coupling::test;

namespace
{
  /// A 10 mm flat punch into an elastic basalt block 36 x 36 x 18 mm at 2 mm spacing.
  CaseParameters elastic_punch()
  {
    CaseParameters p;
    p.test                  = "indentation";
    p.rock.model            = sph::RockModel::elastic;
    p.rock.youngs_modulus   = 97.07e9; // group M1, Table 3
    p.rock.poissons_ratio   = 0.28;
    p.sph.spacing           = 2e-3;
    p.platens.steel.model         = fem::SteelModel::rigid;
    p.cutter.shape          = "flat";
    p.cutter.indenter_width = 0.01;
    p.cutter.penetration    = 2e-4; // 0.1 dx: small strain, linear elasticity
    p.cutter.speed          = 0.4;  // ~ 6e-5 of the P-wave speed: quasi-static
    p.cutter.block_length   = 0.036;
    p.cutter.block_width    = 0.036;
    p.cutter.block_height   = 0.018;
    p.output.n_history_rows = 40;
    p.output.n_snapshots    = 0;
    p.sph.n_threads         = 1; // small body: threads would only wait at barriers
    return p;
  }
} // namespace

TEST(Indentation, FlatPunchFollowsBoussinesqInSeriesWithThePenaltyLayer)
{
  Keep keep;
  const CaseParameters p = elastic_punch();
  const Summary s        = run_case(p, keep);
  ASSERT_GT(keep.rows.size(), 20u);
  const double depth = extra(s, "penetration_mm") * 1e-3;
  const double force = extra(s, "final_normal_force_kN") * 1e3;
  const double n_c   = extra(s, "n_contact_particles");
  const double k_c   = extra(s, "contact_stiffness_N_m");
  ASSERT_GT(n_c, 4.0) << "the punch must touch several particles, or the test proves nothing";
  EXPECT_NEAR(depth, p.cutter.penetration, 1e-9);
  // Boussinesq's half-space stiffness 2 a E/(1 - nu^2) in series with the penalty springs of the
  // particles under the punch (n_c k_c): the contact layer is part of the model, not an error
  const double k_b   = flat_punch_force(97.07e9, 0.28, 0.005, 1.0);
  const double k     = 1.0 / (1.0 / k_b + 1.0 / (n_c * k_c));
  const double ratio = force / (k * depth);
  // 25 %: the block is finite (bottom held at 3.6 a, sides at 3.1 a from the axis: stiffer than a
  // half-space, by 10-20 % for such a layer), the punch's polygonal rim and the lattice count of
  // contact particles set the true contact radius to within half a spacing (a = 5 mm, dx = 2 mm)
  EXPECT_GT(ratio, 0.9);
  EXPECT_LT(ratio, 1.25);
  // linear: the force at half the depth is half the end force (10 %: the sin^2 start-up ramp)
  const HistoryRow *half = nullptr;
  for (const auto &r : keep.rows)
    if (!half && r.displacement >= 0.5 * depth)
      half = &r;
  ASSERT_NE(half, nullptr);
  EXPECT_NEAR(half->force / half->displacement / (force / depth), 1.0, 0.1);
  // force balance: the cutter's contact force equals the supports' reaction (quasi-static;
  // 3 %: the stress waves of the loading still ring at 0.4 m/s)
  const auto &last = keep.rows.back();
  EXPECT_NEAR(last.force_bottom / last.force, 1.0, 0.03);
  // a centred, symmetric punch feels no side force (round-off of the force sums)
  EXPECT_LT(std::abs(last.side_force), 1e-6 * last.force);
}

TEST(CsmEstimate, MatchesAHandCalculation)
{
  // 17-inch disc, T = 12.7 mm, p = 5 mm, S = 75 mm, sigma_c = 200 MPa, sigma_t = 15 MPa, psi = 0.2,
  // worked separately (Python, double precision): phi = acos((R - p)/R) = 0.2156331 rad,
  // P0 = 2.12 (S sc^2 st / (phi sqrt(R T)))^(1/3) = 336.1183 MPa, F_t = P0 phi R T / 1.2 =
  // 165.6085 kN, F_n = F_t cos(phi/2) = 164.6469 kN, F_r = F_t sin(phi/2) = 17.82077 kN
  const CsmEstimate e = csm_cutter_force(200e6, 15e6, 0.2159, 0.0127, 0.005, 0.075, 0.2);
  // 1e-6: the hand values are quoted to 7 digits
  EXPECT_NEAR(e.contact_angle / 0.2156331, 1.0, 1e-6);
  EXPECT_NEAR(e.base_pressure / 336.1183e6, 1.0, 1e-6);
  EXPECT_NEAR(e.total / 165.6085e3, 1.0, 1e-6);
  EXPECT_NEAR(e.normal / 164.6469e3, 1.0, 1e-6);
  EXPECT_NEAR(e.rolling / 17.82077e3, 1.0, 1e-6);
}

namespace
{
  /// A small linear cut: a 60 mm disc, 6 mm tip, 4 mm deep, 28 mm across a basalt block
  /// 60 x 20 x 20 mm at 2 mm spacing (3,000 particles; Mohr-Coulomb, group M1), entering through
  /// the free end face x = 0. Small so that it runs in a minute or two; forces are not compared
  /// with CSM here (two particles over the depth, README).
  CaseParameters small_cut()
  {
    CaseParameters p;
    p.test                  = "linear-cutting";
    p.rock.model            = sph::RockModel::mohr_coulomb;
    p.sph.spacing           = 2e-3;
    p.platens.steel.model         = fem::SteelModel::rigid;
    p.cutter.shape          = "disc";
    p.cutter.disc_diameter  = 0.06;
    p.cutter.tip_width      = 0.006;
    p.cutter.penetration    = 4e-3;
    p.cutter.speed          = 8;
    p.cutter.cut_length     = 0.028;
    p.cutter.block_length   = 0.06;
    p.cutter.block_width    = 0.02;
    p.cutter.block_height   = 0.02;
    p.output.n_history_rows = 60;
    p.output.n_snapshots    = 0;
    p.sph.n_threads         = 1;
    return p;
  }
} // namespace

TEST(LinearCutting, EnergyAndForceBalanceOfASmallCut)
{
  Keep keep;
  const CaseParameters p = small_cut();
  const Summary s        = run_case(p, keep);
  ASSERT_GT(keep.rows.size(), 30u);
  // the path: no plunge, the tip at the penetration throughout, the whole cut length travelled
  EXPECT_NEAR(extra(s, "penetration_mm"), 4.0, 1e-9);
  EXPECT_NEAR(extra(s, "travel_mm"), 28.0, 0.01); // 0.01 mm: the ramps' quadrature
  // the cutter cuts: it carries load, breaks rock out, and some of it leaves the contact. Not the
  // mean over the steady window: entering at full depth breaks the block's top out ahead of the
  // disc (the "entry blow-out" of cases/linear-cutting/README.md), and whether the disc meets
  // rock again before the end of this short cut depends on the time step (main after the
  // contact-spring time-step change: no contact from 8 mm on, so the window mean is 0)
  EXPECT_GT(s.peak_force, 0.0);
  EXPECT_GT(extra(s, "n_chip_particles_released"), 0.0);
  // energy: the cutter's work equals kinetic + stored + dissipated energy (including the penalty
  // energy released with the chip) to 5 % (explicit integration of a violently failing solid;
  // measured 1-2 %)
  EXPECT_LT(s.energy_balance_error, 0.05);
  // a groove on the block's centre line: the side force is small against the normal force
  // (lattice and failure asymmetry; 10 %), judged at the peak
  double peak_side = 0;
  for (const auto &r : keep.rows)
    peak_side = std::max(peak_side, std::abs(r.side_force));
  EXPECT_LT(peak_side, 0.1 * s.peak_force);
}
