// The candidate effects of `cosim diagnose` in the coupled simulator, each against its closed
// form: crack-closure (toe) elasticity of the rock, a compliant load frame in series with the
// platens, and rate-dependent strength. Small UCS runs (5 mm spacing, rigid frictionless platens).
#include "run_helpers.h"

#include <coupling/run_case.h>
#include <sph/rock_models.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace coupling;
using namespace coupling::test;

namespace
{
  constexpr double E  = 97.07e9; // group M1, Table 3 [Pa]
  constexpr double nu = 0.28;
  // Measured 0.57 % (the worst row, near 5 % of the peak; 0.2 % above 20 %); 1.5 % leaves room
  // for the start-up wave, and linear elasticity misses the closed form by 57 %
  constexpr double TOL_CLOSURE = 0.015;
  // The confined closure displacement (a difference of two runs' platen readings, 0.011 mm):
  // measured 1.3 % (the start-up wave read at two platens); a platen following the intact E
  // gave +75 to +80 %; 10 % lies between
  constexpr double TOL_CLOSURE_CTCS = 0.10;
  // Measured 0.26 % (series modulus) and 0.39 % (gauge modulus) with the ramp over 20 transits
  // (0.01 % and 0.03 % over the default 40): the secant is read over 40-60 % of the peak, where
  // the frame's dashpot carries a constant force (no slope); 1 % leaves room for the start-up
  // transient
  constexpr double TOL_FRAME = 0.01;
  // Measured 3.3e-4 with the frame (2.3e-3 without): 1 % catches a frame energy left out (5 %)
  constexpr double TOL_ENERGY = 0.01;
  // Measured 0.36 %: the faster run peaks higher by inertia alone (+0.41 % between 4 and 8 1/s
  // without the effect, 283.72 and 284.88 MPa); 1 % is under a tenth of the 9 % effect
  constexpr double TOL_RATE = 0.01;

  CaseParameters elastic_ucs()
  {
    CaseParameters p;
    p.test                  = "UCS";
    p.rock.model            = sph::RockModel::elastic;
    p.rock.youngs_modulus   = E;
    p.rock.poissons_ratio   = nu;
    p.sph.spacing           = 5e-3;
    p.loading.end_strain    = 1e-3;
    p.output.n_history_rows = 100;
    return p;
  }

  // group M1 with Table 4's c and phi (UCS 282.2 MPa), softening after the peak
  CaseParameters mohr_coulomb_ucs()
  {
    CaseParameters p      = elastic_ucs();
    p.rock.model          = sph::RockModel::mohr_coulomb;
    p.rock.cohesion       = 32.99e6;
    p.rock.friction_angle = 63.68 * M_PI / 180.0;
    p.loading.end_strain  = 0.006;
    // the peak is read on the history rows: 400 resolve it to 0.05 %, and the run stops just
    // past it
    p.output.n_history_rows   = 400;
    p.loading.post_peak_drop  = 0.05;
    return p;
  }
} // namespace

// Crack closure: the stress-strain curve read by the gauges (middle half of the specimen) follows
// the closed-form integral of the law's compliance, eps(sigma) = crack_closure_strain(0, sigma).
TEST(CoupledEffects, CrackClosureCurveFollowsTheClosedForm)
{
  CaseParameters p             = elastic_ucs();
  p.rock.closure_modulus_ratio = 0.4;
  p.rock.closure_stress        = 20e6;
  p.loading.end_strain         = 1.5e-3; // 100 MPa: five closure stresses
  Keep rows;
  const Summary s = run_case(p, rows);
  double worst = 0, linear_worst = 0, top = 0;
  for (const auto &r : rows.rows)
    top = std::max(top, r.stress);
  for (const auto &r : rows.rows)
    if (r.stress > 0.05 * top) // below: the platens' first touch and the start-up wave
      {
        const double closed =
          sph::rock::crack_closure_strain(0.0, r.stress, E, 0.4 * E, 20e6);
        worst        = std::max(worst, std::abs(r.axial_gauge_strain - closed) / closed);
        linear_worst = std::max(linear_worst, std::abs(r.axial_gauge_strain - r.stress / E) / closed);
      }
  std::printf("closure: peak stress %.1f MPa, worst gauge-strain error %.4f (linear E: %.4f)\n",
              top * 1e-6, worst, linear_worst);
  EXPECT_GT(top, 90e6);
  EXPECT_LT(worst, TOL_CLOSURE);
  EXPECT_GT(linear_worst, 5 * TOL_CLOSURE); // the toe is far outside the tolerance: the test sees it
}

// Crack closure under confinement (CTCS at 20 MPa): the platen follows the rock's hydrostatic
// compression with the closure law's tangent modulus while the pressure ramps up, so the
// deviatoric curve starts in contact. The platen displacement from the deviatoric start, minus
// that of the same run without closure (the contact layers and the platens cancel), is the
// closed form L (crack_closure_strain(s3, s3 + q) - q / E) at q = 40-100 % of the top.
// A platen that followed the intact E left a gap of L (1 - 2 nu) int_0^s3 (1/E_t - 1/E) dp
// (0.0085 mm here, 75 % of the 0.011 mm closure displacement) that the loading closed first.
TEST(CoupledEffects, CrackClosureUnderConfinementStartsInContact)
{
  const double s3 = 20e6;
  const auto deviatoric = [s3](CaseParameters p) {
    p.test               = "CTCS";
    p.confining_pressure = s3;
    p.loading.end_strain = 1.5e-3;
    Keep rows;
    run_case(p, rows);
    // the deviatoric curve from its start (the last row at q <= 0.2 % of the top)
    double top = 0;
    for (const auto &r : rows.rows)
      top = std::max(top, r.stress - s3);
    std::size_t i0 = 0;
    for (std::size_t i = 0; i < rows.rows.size() && rows.rows[i].stress - s3 < 0.999 * top; ++i)
      if (rows.rows[i].stress - s3 <= 2e-3 * top)
        i0 = i;
    std::vector<std::pair<double, double>> curve; // (q [Pa], displacement [m])
    for (std::size_t i = i0; i < rows.rows.size(); ++i)
      curve.push_back({rows.rows[i].stress - s3, rows.rows[i].displacement - rows.rows[i0].displacement});
    return std::make_pair(curve, top);
  };
  const auto at = [](const std::vector<std::pair<double, double>> &c, const double q) {
    for (std::size_t i = 1; i < c.size(); ++i)
      if (c[i].first >= q && c[i - 1].first < q)
        return c[i - 1].second + (q - c[i - 1].first) / (c[i].first - c[i - 1].first) *
                                   (c[i].second - c[i - 1].second);
    return std::nan("");
  };
  CaseParameters closure             = elastic_ucs();
  closure.rock.closure_modulus_ratio = 0.4;
  closure.rock.closure_stress        = 20e6;
  const auto [with, top]             = deviatoric(closure);
  const auto [without, top_linear]   = deviatoric(elastic_ucs());
  const double L                     = closure.length;
  double worst                       = 0;
  for (const double f : {0.4, 0.6, 0.8, 1.0})
  {
    const double q      = f * std::min(top, top_linear) * 0.999;
    const double closed = L * (sph::rock::crack_closure_strain(s3, s3 + q, E, 0.4 * E, 20e6) - q / E);
    const double sim    = at(with, q) - at(without, q);
    std::printf("closure at %.0f MPa confinement, q %.1f MPa: extra displacement %.5f mm, closed "
                "form %.5f mm\n",
                s3 * 1e-6, q * 1e-6, sim * 1e3, closed * 1e3);
    worst = std::max(worst, std::abs(sim - closed) / closed);
  }
  EXPECT_GT(top, 90e6);
  EXPECT_LT(worst, TOL_CLOSURE_CTCS);
}

// Load-frame compliance: with a frame spring k_frame between the actuator and the top platen, the
// modulus read at the actuator is the specimen's (as read without a frame: rock, contact layers)
// in series with the frame, k = 1 / (1/k_rock + 1/k_frame). k_frame = k_rock halves it.
TEST(CoupledEffects, LoadFrameComplianceGivesTheSeriesModulus)
{
  // a ramp over 20 wave transits (half the default, for time): still quasi-static
  CaseParameters p        = elastic_ucs();
  p.loading.transit_times = 20;
  Keep rows0;
  const Summary s0     = run_case(p, rows0);
  const double  L      = 0.1;
  const double  k_rock = s0.platen_modulus * s0.true_area / L; // [N/m]
  p.platens.frame_stiffness = k_rock;
  Keep rows;
  const Summary s      = run_case(p, rows);
  const double  series = 1.0 / (1.0 / k_rock + 1.0 / p.platens.frame_stiffness) * L / s0.true_area;
  std::printf("frame: k_rock %.4g N/m, platen modulus %.4g GPa without the frame, %.4g GPa with "
              "(series closed form %.4g GPa, ratio %.5f); gauge modulus %.4g / %.4g GPa\n",
              k_rock, s0.platen_modulus * 1e-9, s.platen_modulus * 1e-9, series * 1e-9,
              s.platen_modulus / series, s0.youngs_modulus * 1e-9, s.youngs_modulus * 1e-9);
  std::printf("frame: energy balance error %.2e (without the frame %.2e)\n", s.energy_balance_error,
              s0.energy_balance_error);
  EXPECT_NEAR(s.platen_modulus / series, 1.0, TOL_FRAME);
  // the rock itself sees the same load path: its gauge modulus does not change
  EXPECT_NEAR(s.youngs_modulus / s0.youngs_modulus, 1.0, TOL_FRAME);
  // the frame's spring and dashpot are in the energy account
  EXPECT_LT(s.energy_balance_error, TOL_ENERGY);
  EXPECT_NEAR(extra(s, "frame_stiffness_N_per_m"), k_rock, 1e-6 * k_rock);
}

// Rate-dependent strength: two loading rates a factor 2 apart with the reference rate at the
// slower one, so the closed-form peak ratio is 1 + A log10(2).
TEST(CoupledEffects, RateDependentPeakRatioIsTheClosedForm)
{
  constexpr double A = 0.3, r1 = 4.0, r2 = 8.0; // [-], [1/s], [1/s]
  CaseParameters   p                  = mohr_coulomb_ucs();
  p.rock_case.rate_sensitivity        = A;
  p.rock_case.reference_strain_rate   = r1;
  p.loading.strain_rate               = r1;
  Keep rows1, rows2;
  const Summary s1 = run_case(p, rows1);
  p.loading.strain_rate = r2;
  const Summary s2      = run_case(p, rows2);
  const double  closed  = sph::rock::rate_strength_factor(r2, r1, A) /
                       sph::rock::rate_strength_factor(r1, r1, A);
  std::printf("rate: peaks %.2f MPa at %g 1/s, %.2f MPa at %g 1/s; ratio %.5f, closed form %.5f\n",
              s1.peak_stress * 1e-6, r1, s2.peak_stress * 1e-6, r2, s2.peak_stress / s1.peak_stress,
              closed);
  EXPECT_NEAR((s2.peak_stress / s1.peak_stress) / closed, 1.0, TOL_RATE);
  EXPECT_NEAR(extra(s2, "rate_strength_factor"), closed, 1e-12);
}

// The BTS displacement at peak (cases/diagnose-basalt/README.md): the M1 disc at 2.5 mm, rigid
// frictionless platens. A frame spring in series adds P / k to the stroke at the peak and leaves
// the strength; crack closure with the same order of extra displacement also raises the disc's
// strength (the soft compressed zones under the platens spread the load), which is what tells the
// two apart in that README.
TEST(CoupledEffects, BtsDisplacementFrameAddsPOverKClosureAlsoRaisesTheStrength)
{
  CaseParameters p      = mohr_coulomb_ucs();
  p.test                = "BTS";
  p.length              = 0.025;
  p.sph.spacing         = 2.5e-3;
  p.loading.end_strain  = 0.004;
  p.loading.post_peak_drop = 0.2;
  p.output.n_history_rows  = 400;
  RunObserver quiet;
  const Summary base = run_case(p, quiet);
  CaseParameters pf  = p;
  pf.platens.frame_stiffness = 5.6e8;
  const Summary frame = run_case(pf, quiet);
  CaseParameters pc  = p;
  pc.rock.closure_modulus_ratio = 0.2;
  pc.rock.closure_stress        = 20e6;
  const Summary closure = run_case(pc, quiet);
  const double D = p.diameter;
  const double added = (frame.strain_at_peak - base.strain_at_peak) * D;
  const double p_over_k = frame.peak_force / pf.platens.frame_stiffness;
  std::printf("BTS displacement at peak: base %.4f mm (%.2f MPa), frame %.4f mm (%.2f MPa; added "
              "%.4f mm against P/k %.4f mm), closure %.4f mm (%.2f MPa)\n",
              base.strain_at_peak * D * 1e3, base.peak_stress * 1e-6, frame.strain_at_peak * D * 1e3,
              frame.peak_stress * 1e-6, added * 1e3, p_over_k * 1e3, closure.strain_at_peak * D * 1e3,
              closure.peak_stress * 1e-6);
  // measured -3.9 %: the stroke is read on the history rows and the frame's dashpot carries a
  // small force at the peak; 10 % is well inside the factor 2.9 the frame adds
  EXPECT_NEAR(added / p_over_k, 1.0, 0.10);
  // measured -1.0 %: the frame leaves the strength (2 %: the post-peak path differs)
  EXPECT_NEAR(frame.peak_stress / base.peak_stress, 1.0, 0.02);
  // measured +19 % (+13 % at 1.25 mm) and 2.7 times the displacement: far outside either bound
  EXPECT_GT(closure.peak_stress / base.peak_stress, 1.08);
  EXPECT_GT(closure.strain_at_peak / base.strain_at_peak, 2.0);
}
