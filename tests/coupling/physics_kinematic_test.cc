// The specimen tests with the kinematic interface (Platens/Contact method = kinematic): no
// contact stiffness, so the moduli, the strengths and the energy account must come out of the
// rock and the steel alone. The cases are the shipped case files (group M1, rigid frictionless
// platens, 2.5 mm) with the settings each test names, one thread each (ctest runs two tests at a
// time on two cores).
#include "run_helpers.h"

#include <app/case_file.h>
#include <coupling/curve_analysis.h>
#include <coupling/reference_cylinder.h>
#include <coupling/references.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>
#include <tuple>
#include <vector>

using namespace coupling;
using namespace coupling::test;

namespace
{
  /// A shipped case as `cosim run` runs it (its own rock, the simulator's Hoek-Brown, and its
  /// history rows, which sample the peak), on one thread.
  CaseParameters default_case(const std::string &name, const std::vector<std::string> &settings)
  {
    CaseParameters p =
      app::read_case_file(std::string(COSIM_SOURCE_DIR) + "/cases/" + name, settings).parameters;
    p.sph.n_threads   = 1;
    p.output.progress = false;
    return p;
  }

  /// The same with Mohr-Coulomb rock (the simulator's c, phi unless `settings` say otherwise):
  /// the rock of the FE reference and of the closed forms these tests compare with.
  CaseParameters kinematic_case(const std::string &name, std::vector<std::string> settings)
  {
    settings.insert(settings.begin(), "Rock/Model=mohr-coulomb");
    settings.push_back("Platens/Contact method=kinematic");
    CaseParameters p =
      app::read_case_file(std::string(COSIM_SOURCE_DIR) + "/cases/" + name, settings).parameters;
    p.sph.n_threads         = 1;
    p.output.n_history_rows = 200;
    p.output.progress       = false;
    return p;
  }

  /// The Mohr-Coulomb uniaxial strength 2c cos(phi)/(1 - sin(phi)) of the shipped UCS case's
  /// rock (Table 4's M1: 282.19 MPa) [Pa].
  double closed_form_ucs()
  {
    const CaseParameters p = kinematic_case("ucs/ucs.prm", {});
    return mohr_coulomb_axial_strength(p.rock.cohesion, p.rock.friction_angle * 180.0 / M_PI, 0.0);
  }
} // namespace

TEST(CoupledKinematic, ElasticUcsShowsNoInterfaceCompliance)
{
  const CaseParameters p =
    kinematic_case("ucs/ucs.prm", {"Rock/Model=elastic", "Loading/End strain=0.001"});
  Keep rows;
  const Summary s = run_case(p, rows);
  // 1 %: the tolerance of the rigid-platen UCS (the gauges over the middle half see SPH's exact
  // uniform field; measured 97.14 GPa against Table 3's 97.07)
  EXPECT_NEAR(s.youngs_modulus / 97.07e9, 1.0, 0.01);
  // what the frame reads has no penalty layer in it, and the end particles' half cells between
  // their centres and the platens strain with them (held at r n.F n): the platen-read modulus is
  // the gauge one. 1 %: as the gauges; measured 97.170 against 97.166 GPa. With rigid half cells
  // it read E L / (L - dx), +2.6 %; the default penalty interface reads 10 % soft at 2.5 mm
  EXPECT_NEAR(s.platen_modulus / s.youngs_modulus, 1.0, 0.01);
  // the constraint adds and takes no energy: 1 % (the interface's target); measured 6e-4
  EXPECT_LT(s.energy_balance_error, 0.01);
  // 1e-12: every pair force applied once to each side
  EXPECT_LT(s.max_exchange_imbalance, 1e-12);
}

TEST(CoupledKinematic, MohrCoulombUcsPeakIsTheClosedFormWithNoEarlyFailure)
{
  const CaseParameters p = kinematic_case("ucs/ucs.prm", {"Loading/End strain=0.005"});
  Keep rows;
  const Summary s = run_case(p, rows);
  // 1 %: Table 3's UCS tolerance; measured 282.93 MPa, +0.26 % (the dynamic overshoot of the
  // loading and the viscous stress, as with the penalty interface). Without the loaded-face
  // correction the end layer fails first at 219.6 MPa (-22 %)
  EXPECT_NEAR(s.peak_stress / closed_form_ucs(), 1.0, 0.01);
  EXPECT_EQ(s.stop_reason, "post-peak drop");
  // no particle fails before the material's strength: the field is uniform, so the whole body
  // yields together (measured: the first failure at 281.95 MPa, 0.09 % below the closed form,
  // in the end layer at r/R 0.73). A constraint without the loaded-face correction fails the end
  // layer first at 96 MPa. 1 %: as the peak
  EXPECT_GT(extra(s, "failure_onset_stress_MPa") * 1e6, 0.99 * closed_form_ucs());
  // 1 %: as the elastic run; measured 5e-4 up to the post-peak drop
  EXPECT_LT(s.energy_balance_error, 0.01);
}

TEST(CoupledKinematic, BtsSplitsFromTheCentreAtTable3Strength)
{
  const CaseParameters p = kinematic_case("bts/bts-round.prm", {});
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  // 3 %: Table 3's BTS tolerance against the measured 15.43 MPa; measured 15.32 MPa (the
  // penalty interface: 14.98)
  EXPECT_NEAR(s.peak_stress / 15.43e6, 1.0, 0.03);
  // the split starts at the centre (measured r/R 0.07; 0.3 R is three spacings) and runs along
  // the loaded diameter, as in the penalty test (CoupledBts.*)
  EXPECT_LT(extra(s, "failure_onset_radius_ratio"), 0.3);
  EXPECT_GT(extra(s, "crack_alignment"), 3.0);
  EXPECT_LT(s.energy_balance_error, 0.01);
}

// The default BTS case (the flattened body-fitted disc at 2.5 mm) with the Mohr-Coulomb rock of
// the simulator's c, phi (simulator_calibrated.csv, calibrated on the same disc at 1.25 mm)
// against Table 3's BTS, for the groups of the steepest and the flattest of those envelopes
// (M10: phi 66.1 deg; M1: 60.5 deg). 3 %: the bound Table 3's BTS is asked to hold at the
// default spacing; measured -2.09 / -1.44 % at 2 mm, the spacing's share (the same disc at 1.25
// mm gives Table 3 within the calibration's 0.5 %). With Table 4's c, phi the disc is 18 % low, so the
// rock cannot fall back to them unnoticed. The split runs along the loaded diameter (measured
// alignment 3.9 / 5.5; M10's failed particles all lie on the loaded diameter, x = 0, at the end:
// the across spread is their own width, where round-off alone once made it 1e16).
TEST(CoupledKinematic, DefaultBtsCaseGivesTable3WithTheSimulatorsRock)
{
  for (const auto &[group, bts] : {std::pair{"M1", 15.43e6}, std::pair{"M10", 7.99e6}})
    {
      CaseParameters p = kinematic_case("bts/bts.prm", {std::string("Rock/Group=") + group});
      ASSERT_EQ(p.rock_case.strength_source, "simulated");
      RunObserver quiet;
      const Summary s = run_case(p, quiet);
      std::printf("%s: peak %.4f MPa (Table 3 %.2f), alignment %.2f\n", group, s.peak_stress / 1e6,
                  bts / 1e6, extra(s, "crack_alignment"));
      EXPECT_NEAR(s.peak_stress / bts, 1.0, 0.03) << group;
      EXPECT_EQ(s.stop_reason, "post-peak drop") << group;
      EXPECT_GT(extra(s, "crack_alignment"), 3.0) << group;
      EXPECT_LT(extra(s, "crack_alignment"), 100.0) << group; // a spread, not round-off
    }
}

// The default cases' rock, Hoek-Brown with the simulator's envelope (simulator_calibrated.csv):
// M1 and M4 without triaxial data (a = 1/2, the m_b that calibrate --simulate --mb-from fitted
// to the BTS on the flattened disc at 1.25 mm, no cut-off but the apex), M10 its triaxial
// envelope with the cut-off fitted the same way. At the default spacings (cylinder 2.5 mm, disc
// 2 mm): UCS within 1 % (sigma_ci is the UCS; M4's cylinder measured +0.29 %, the loading rate's
// overshoot); BTS within 2.5 % (measured -0.80 / -1.32 / -1.22 %): the disc at 2 mm lies up to
// 1.6 % below its 1.25 mm calibration (study bts-groups-hb; M1 14.85 MPa at 2.5 mm, 3.8 % low,
// would fail this) and the calibration holds Table 3 within 0.5 %: 2.1 %, with 0.4 % to spare
// below the 3 % asked of the BTS. The split runs along the
// loaded diameter.
TEST(CoupledKinematic, DefaultCasesGiveTable3WithTheirHoekBrownRock)
{
  for (const auto &[group, bts] :
       {std::pair{"M1", 15.43e6}, std::pair{"M4", 9.60e6}, std::pair{"M10", 7.99e6}})
    {
      CaseParameters disc = default_case("bts/bts.prm", {std::string("Rock/Group=") + group});
      ASSERT_EQ(disc.rock.model, sph::RockModel::hoek_brown);
      ASSERT_EQ(disc.rock_case.strength_source, "simulated");
      RunObserver quiet;
      const Summary b = run_case(disc, quiet);
      std::printf("%s Hoek-Brown: BTS %.4f MPa (Table 3 %.2f), alignment %.2f\n", group, b.peak_stress / 1e6,
                  bts / 1e6, extra(b, "crack_alignment"));
      EXPECT_NEAR(b.peak_stress / bts, 1.0, 0.025) << group;
      EXPECT_EQ(b.stop_reason, "post-peak drop") << group;
      EXPECT_GT(extra(b, "crack_alignment"), 3.0) << group;
    }
  CaseParameters cylinder = default_case("ucs/ucs.prm", {"Rock/Group=M4"});
  ASSERT_EQ(cylinder.rock.hb_a, 0.5);
  ASSERT_EQ(cylinder.rock.tensile_strength, 0.0);
  RunObserver quiet;
  const Summary u = run_case(cylinder, quiet);
  std::printf("M4 Hoek-Brown: UCS %.3f MPa (Table 3 200.18)\n", u.peak_stress / 1e6);
  EXPECT_NEAR(u.peak_stress / 200.18e6, 1.0, 0.01);
}

namespace
{
  /// The UCS case with a perfectly plastic rock (no softening, as the FE reference) to 0.5 %:
  /// Mohr-Coulomb (kinematic_case), or the case's own Hoek-Brown rock (default_case; M1: sigma_ci
  /// 282.18 MPa, m_b 16.43, a 1/2, psi 0).
  CaseParameters perfectly_plastic_ucs(std::vector<std::string> settings, const bool hoek_brown = false)
  {
    settings.push_back("Rock/Residual fraction=1");
    settings.push_back("Loading/End strain=0.005");
    return hoek_brown ? default_case("ucs/ucs.prm", settings) : kinematic_case("ucs/ucs.prm", settings);
  }

  /// cosim reference's solution of the perfectly plastic case p with bonded ends on `platens`
  /// (Q2, 8 elements per radius, 60 increments to 0.6 % strain; the Hoek-Brown tests 35 to
  /// 0.35 %: its peak lies at 0.27-0.29 %, and past it Newton stalls, as with Mohr-Coulomb and
  /// psi = 0)
  ReferenceResult bonded_reference(const CaseParameters &p, const ReferencePlatens platens,
                                   const unsigned int n_increments = 60, const double end_strain = 0.006)
  {
    ReferenceOptions o;
    o.interface    = ReferenceInterface::bonded;
    o.platens      = platens;
    o.n_radial     = 8;
    o.n_increments = n_increments;
    o.end_strain   = end_strain;
    return run_reference_cylinder(p, o);
  }

  double peak(const CaseParameters &p)
  {
    RunObserver quiet;
    return run_case(p, quiet).peak_stress;
  }

  /// The perfectly plastic cylinder between rigid platens at 5 mm (for time): its peaks with
  /// free-slip ends, Coulomb friction 0.1 and 0.3, and bonded ends [Pa].
  std::array<double, 4> end_friction_peaks(const bool hoek_brown)
  {
    std::array<double, 4> out{};
    const char *ends[] = {"Platens/Friction coefficient=0", "Platens/Friction coefficient=0.1",
                          "Platens/Friction coefficient=0.3", "Platens/Bonded=true"};
    for (int k = 0; k < 4; ++k)
      out[k] = peak(perfectly_plastic_ucs({"SPH/Particle spacing=0.005", ends[k]}, hoek_brown));
    return out;
  }

  /// At each snapshot: the top end layer's axial stress (compression +) in ten radial rings of
  /// equal width, and the load, the mean axial stress of the middle layer [Pa].
  class EndFaceObserver : public RunObserver
  {
  public:
    struct Profile
    {
      double load = 0;
      std::vector<double> r, axial, area; ///< ring: mean radius [m], mean stress [Pa], r_o^2 - r_i^2
    };
    explicit EndFaceObserver(const double spacing, const double radius)
        : dx_(spacing)
        , radius_(radius)
    {}
    std::vector<Profile> profiles;

    void snapshot(double, const ParticleSnapshot &s, const std::vector<MeshSnapshot> &) override
    {
      const std::size_t n = s.n_rows();
      double z_lo = 1e300, z_hi = -1e300;
      for (std::size_t i = 0; i < n; ++i)
        z_lo = std::min(z_lo, s.position[3 * i + 2]), z_hi = std::max(z_hi, s.position[3 * i + 2]);
      const int rings = 10;
      std::vector<double> sum_r(rings, 0), sum_s(rings, 0), count(rings, 0);
      double mid_sum = 0, mid_count = 0;
      for (std::size_t i = 0; i < n; ++i)
      {
        const double *x = &s.position[3 * i];
        const double szz = -s.stress[6 * i + 2]; // components xx, yy, zz, yz, xz, xy
        if (std::abs(x[2] - 0.5 * (z_lo + z_hi)) < 0.5 * dx_)
          mid_sum += szz, mid_count += 1;
        if (x[2] < z_hi - 0.25 * dx_)
          continue;
        const double r = std::hypot(x[0], x[1]);
        const int k    = std::min(rings - 1, static_cast<int>(r / radius_ * rings));
        sum_r[k] += r, sum_s[k] += szz, count[k] += 1;
      }
      Profile p;
      p.load = mid_count > 0 ? mid_sum / mid_count : 0;
      for (int k = 0; k < rings; ++k)
        if (count[k] > 0)
        {
          p.r.push_back(sum_r[k] / count[k]);
          p.axial.push_back(sum_s[k] / count[k]);
          p.area.push_back(std::pow((k + 1.0) / rings, 2) - std::pow(double(k) / rings, 2));
        }
      profiles.push_back(p);
    }

  private:
    double dx_, radius_;
  };

  /// The area-weighted RMS over the end face of the coupled axial stress at half the coupled
  /// peak against the reference's at half its peak, each divided by its load (the coupled
  /// middle layer's mean, the reference's force over the section): the snapshot nearest half
  /// the peak, the reference's Gauss points interpolated linearly in r.
  double end_face_rms(const EndFaceObserver &o, const double coupled_peak, const ReferenceResult &r,
                      const double radius)
  {
    const EndFaceObserver::Profile *best = nullptr;
    for (const auto &p : o.profiles)
      if (!best || std::abs(p.load - 0.5 * coupled_peak) < std::abs(best->load - 0.5 * coupled_peak))
        best = &p;
    if (!best || r.end_face.size() < 2)
      return 1e300;
    const double reference_load = r.half_peak_force / (M_PI * radius * radius);
    double sum = 0, weight = 0;
    for (std::size_t k = 0; k < best->r.size(); ++k)
    {
      const double rk = best->r[k];
      std::size_t j   = 1;
      while (j + 1 < r.end_face.size() && r.end_face[j].r < rk)
        ++j;
      const auto &a = r.end_face[j - 1], &b = r.end_face[j];
      const double t   = std::clamp((rk - a.r) / (b.r - a.r), 0.0, 1.0);
      const double ref = (1 - t) * a.axial_stress + t * b.axial_stress;
      const double e   = best->axial[k] / best->load - ref / reference_load;
      sum += best->area[k] * e * e;
      weight += best->area[k];
    }
    return std::sqrt(sum / weight);
  }
} // namespace

TEST(CoupledKinematic, EndFrictionLiesBetweenFreeSlipAndBondedEnds)
{
  // rigid platens, 5 mm (for time): Coulomb friction must give a peak between the free-slip and
  // the bonded one, and more friction must hold the ends more. With this rock (Mohr-Coulomb,
  // psi = 0) held ends weaken the cylinder, as the FE reference does (next test). Measured:
  // 283.50 / 274.65 / 259.63 / 247.43 MPa
  const auto [free_slip, mu_01, mu_03, bonded] = end_friction_peaks(false);
  // 1 %: the closed form on free-slip ends (perfect plasticity: the plateau)
  EXPECT_NEAR(free_slip / closed_form_ucs(), 1.0, 0.01);
  EXPECT_LT(mu_01, free_slip);
  EXPECT_LT(mu_03, mu_01);
  EXPECT_LT(bonded, mu_03);
  // the ends hold: bonded is well below free slip (a friction read but not applied gives 1.0)
  EXPECT_LT(bonded / free_slip, 0.95);
}

TEST(CoupledKinematic, BondedRigidPlatensGiveTheFeReferencePeak)
{
  // the coupled cylinder with bonded rigid ends against the independent implicit FE solution
  // (cosim reference, axisymmetric Q2, 8 elements per radius) of the same perfectly plastic rock.
  // 2 %: the interface's target against the reference; measured 256.49 against 255.98 MPa
  // (+0.2 %); the reference itself moves 1.2 % between 4 and 8 elements per radius
  CaseParameters p = perfectly_plastic_ucs({"Platens/Bonded=true", "Output/Snapshots=80"});
  EndFaceObserver face(p.sph.spacing, 0.5 * p.diameter);
  const double coupled    = run_case(p, face).peak_stress;
  const ReferenceResult r = bonded_reference(p, ReferencePlatens::rigid);
  const double rms        = end_face_rms(face, coupled, r, 0.5 * p.diameter);
  std::cout << "[bonded] coupled " << coupled / 1e6 << " MPa, reference " << r.peak_stress / 1e6
            << " MPa (" << r.end_reason << "); end face at half the peak: RMS " << rms << "\n";
  EXPECT_NEAR(coupled / r.peak_stress, 1.0, 0.02);
  // the axial stress along the end face at half the peak, held ends (the reference: 112.7 MPa
  // at the centre, 220.6 at its outermost Gauss point): 5 % RMS over the face, the interface's
  // target, each profile over its own load. The coupled end layer is 1.25 mm deep, the
  // reference's Gauss points 0.35 mm: its rim is sharper, which the RMS takes in. Measured
  // 3.8 %; a uniform profile (free slip) would be 20 % off
  EXPECT_LT(rms, 0.05);
  // and both below free slip: held ends weaken a psi = 0 cylinder (282.19 MPa free slip;
  // measured 0.907 of it). 0.95: well clear of a reference whose ends do not hold (1.0)
  EXPECT_LT(r.peak_stress, 0.95 * closed_form_ucs());
}

TEST(CoupledKinematic, BondedElasticPlatensGiveTheFeReferencePeakAndEndFace)
{
  // steel platens (20 mm, 60 mm wide, 5 mm elements, clamped to the rams) bonded to the
  // perfectly plastic cylinder, against cosim reference's Q2 solution of the same (8 elements
  // per radius; 4 / 8: 269.40 / 268.99 MPa, converged; Newton stalls past the peak, a lower
  // bound by the plateau)
  CaseParameters p = perfectly_plastic_ucs({"Platens/Model=elastic", "Platens/Bonded=true", "Output/Snapshots=80"});
  EndFaceObserver face(p.sph.spacing, 0.5 * p.diameter);
  const double coupled    = run_case(p, face).peak_stress;
  const ReferenceResult r = bonded_reference(p, ReferencePlatens::elastic);
  const double rms        = end_face_rms(face, coupled, r, 0.5 * p.diameter);
  std::cout << "[elastic bonded] coupled " << coupled / 1e6 << " MPa, reference " << r.peak_stress / 1e6
            << " MPa; end face at half the peak: RMS " << rms << "\n";
  // 2 %: the interface's target against the reference; measured 273.36 against 268.99 MPa
  // (+1.6 %; 270.73 with the held distance lagged a step, 270.64 before the contact points were
  // mapped, ContactParameters::face_radius_mapped)
  EXPECT_NEAR(coupled / r.peak_stress, 1.0, 0.02);
  // 5 % RMS over the face, as with rigid bonded ends (the test above); measured 3.1 % (2.3 %
  // before the contact points were mapped)
  EXPECT_LT(rms, 0.05);
}

TEST(CoupledKinematic, HoekBrownEndFrictionLiesBetweenTheFeReferencesFreeSlipAndBondedPeaks)
{
  // The cases' default rock between rigid platens: Coulomb friction of 0.1 and 0.3 must give
  // peaks between the FE reference's free-slip and bonded ones (the interface's target), in
  // order. 5 mm for time. Measured: coupled 283.41 / 279.74 / 271.51 / 267.56 MPa at mu 0 / 0.1
  // / 0.3 / bonded (2.5 mm: 283.50 / 279.21 / 271.18 / 269.29); reference free slip 282.18
  // (sigma_ci, a limit load on any mesh), bonded 268.29 (4 / 8 / 16 elements per radius: 270.02
  // / 268.29 / >= 267.51, the finest stalled while still rising). Table 4's Mohr-Coulomb rock
  // (the tests above) lies between its own references too, its held ends costing it far more
  // (mu 0.3 at 2.5 mm: 259.14 MPa, bonded reference 255.98; cases/studies/platens/README.md).
  const auto [free_slip, mu_01, mu_03, bonded] = end_friction_peaks(true);
  const CaseParameters p = perfectly_plastic_ucs({}, true);
  ReferenceOptions o;
  o.n_radial                  = 4;
  o.n_increments              = 35;
  o.end_strain                = 0.0035;
  const double reference_free = run_reference_cylinder(p, o).peak_stress;
  const ReferenceResult held  = bonded_reference(p, ReferencePlatens::rigid, 35, 0.0035);
  std::cout << "[hoek-brown] coupled " << free_slip / 1e6 << " / " << mu_01 / 1e6 << " / "
            << mu_03 / 1e6 << " / " << bonded / 1e6 << " MPa; reference " << reference_free / 1e6
            << " / " << held.peak_stress / 1e6 << " MPa (" << held.end_reason << ")\n";
  // the reference's free slip is sigma_ci s^a (1e-4: its limit-load detection, as on rollers)
  EXPECT_NEAR(reference_free / (p.rock.hb_sigma_ci * std::pow(p.rock.hb_s, p.rock.hb_a)), 1.0, 1e-4);
  // 1 %: the coupled free slip against it (perfect plasticity's plateau; measured +0.44 %)
  EXPECT_NEAR(free_slip / reference_free, 1.0, 0.01);
  // strictly between the two references (measured 0.9914 and 1.0120 of free slip and bonded)
  EXPECT_LT(mu_01, reference_free);
  EXPECT_GT(mu_03, held.peak_stress);
  EXPECT_LT(mu_03, mu_01);
  // 2 %: the coupled bonded ends against the reference's, the interface's target (measured -0.27 %)
  EXPECT_NEAR(bonded / held.peak_stress, 1.0, 0.02);
  // the ends hold: bonded well below free slip (a bond read but not applied gives 1.0)
  EXPECT_LT(held.peak_stress, 0.97 * reference_free);
}

TEST(CoupledKinematic, HoekBrownBondedPlatensGiveTheFeReferencePeakAndEndFace)
{
  // The same rock at the case's 2.5 mm, bonded to rigid and to elastic steel platens (20 mm,
  // 60 mm wide, 5 mm elements), against the reference: peak within 2 % and the end face's axial
  // stress at half the peak within 5 % RMS, the interface's targets (as the Mohr-Coulomb tests
  // above). Measured: rigid 269.29 against 268.29 MPa (+0.37 %); elastic 279.89 against 276.36
  // (+1.28 %; Newton stalls at the peak on 8 elements per radius, 4 give 276.61, complete); end
  // face RMS 3.75 % rigid, 3.06 % elastic.
  for (const bool elastic : {false, true})
  {
    std::vector<std::string> s{"Platens/Bonded=true", "Output/Snapshots=80"};
    if (elastic)
      s.push_back("Platens/Model=elastic");
    const CaseParameters p = perfectly_plastic_ucs(s, true);
    EndFaceObserver face(p.sph.spacing, 0.5 * p.diameter);
    const double coupled    = run_case(p, face).peak_stress;
    const ReferenceResult r = bonded_reference(
      p, elastic ? ReferencePlatens::elastic : ReferencePlatens::rigid, 35, 0.0035);
    const double rms = end_face_rms(face, coupled, r, 0.5 * p.diameter);
    std::cout << "[hoek-brown bonded, " << (elastic ? "elastic" : "rigid") << "] coupled "
              << coupled / 1e6 << " MPa, reference " << r.peak_stress / 1e6 << " MPa ("
              << r.end_reason << "); end face at half the peak: RMS " << rms << "\n";
    EXPECT_NEAR(coupled / r.peak_stress, 1.0, 0.02) << (elastic ? "elastic" : "rigid");
    EXPECT_LT(rms, 0.05) << (elastic ? "elastic" : "rigid");
  }
}

TEST(CoupledKinematic, SofteningUnderFrictionHeldEndsConvergesWithAShearFaultsFractureEnergy)
{
  // The cases' rock softening by the crack band between rigid platens with end friction 0.3, its
  // shear and crushing returns dissipating a shear fault's G_II = 100 G_I = 1e4 J/m^2 (Wong
  // 1982): the band (2 dx) is then narrower than 2 E G_II / UCS^2 = 24 mm and compressive failure
  // is regularised. Measured 270.80 / 270.68 MPa at 2.5 / 1.25 mm (5 mm: 270.69). With the
  // default G_II = 6.25 G_I (that limit 1.5 mm: every band snaps back) 262.65 / 257.28 / 238.76
  // at 5 / 2.5 / 1.25 mm, with the strain law 269.16 / 268.74 / 243.09: neither converges
  // (cases/studies/platens/README.md). 2.5 and 1.25 mm, where the others part: 200-240 s.
  // Finer, the lattice holds to 1 mm (270.45 MPa) but falls to 245.70 / 246.23 at 0.83 / 0.8 mm:
  // a particle cracked to its residual at a staircase step under the held end is pushed out by its
  // loaded neighbours and the rim fails around it. Body-fitted rings have no step and converge:
  // 271.62 / 271.12 / 270.93 / 270.60 MPa at 2.5 / 1.25 / 1 / 0.83 mm (0.83 mm: 16 minutes, too
  // long here); the test runs their 2.5 mm (about 30 s on one thread) against the lattice's 1.25 mm.
  const std::vector<std::string> crack_band{"Rock/Softening law=fracture energy",
                                            "Rock/Shear fracture energy ratio=100",
                                            "Platens/Friction coefficient=0.3"};
  std::array<double, 2> softening{};
  const char *spacing[] = {"SPH/Particle spacing=0.0025", "SPH/Particle spacing=0.00125"};
  for (int k = 0; k < 2; ++k)
  {
    std::vector<std::string> s = crack_band;
    s.push_back(spacing[k]);
    softening[k] = peak(default_case("ucs/ucs.prm", s));
  }
  const double plastic = peak(perfectly_plastic_ucs({"Platens/Friction coefficient=0.3"}, true));
  std::cout << "[held ends, crack band] " << softening[0] / 1e6 << " / " << softening[1] / 1e6
            << " MPa at 2.5 / 1.25 mm; perfectly plastic " << plastic / 1e6 << " MPa\n";
  // 1 %: the convergence asked of a quoted peak (measured -0.04 %)
  EXPECT_NEAR(softening[1] / softening[0], 1.0, 0.01);
  // 1 %: the rock softens so gradually at this G_II that the specimen's peak is its perfectly
  // plastic limit (271.18 MPa at 2.5 mm, within the FE reference's bonded and free-slip peaks,
  // the test above; measured -0.14 %); a peak that collapsed with the spacing, as the default
  // G_II's, falls 2-12 % short
  EXPECT_NEAR(softening[0] / plastic, 1.0, 0.01);
  // and not above it: softening only takes strength away; 0.1 % for the two runs' different
  // step sequences through the same explicit loading (measured 0.14 % below)
  EXPECT_LE(softening[0], plastic * 1.001);

  std::vector<std::string> s = crack_band;
  s.push_back("SPH/Particle arrangement=body-fitted");
  const double fitted = peak(default_case("ucs/ucs.prm", s));
  std::cout << "[held ends, crack band] body-fitted " << fitted / 1e6 << " MPa at 2.5 mm\n";
  // 0.5 %: half the convergence criterion, between two particle sets that share no particle
  // (measured +0.35 % of the lattice's 1.25 mm), and of the body-fitted 0.83 mm peak 270.60 MPa
  // (cases/studies/platens/README.md; measured +0.38 %), which the lattice misses by 9 %
  EXPECT_NEAR(fitted / softening[1], 1.0, 0.005);
  EXPECT_NEAR(fitted / 270.60e6, 1.0, 0.005);
}

TEST(CoupledKinematic, WideSteelPlatensWithFrictionConvergeInSpacingAndMesh)
{
  // The same crack band (G_II = 100 G_I) and mu 0.3 on elastic steel platens 1.2 D wide, the
  // platens users run: over 5 / 2.5 / 1.25 mm particles on 10 / 5 / 2.5 mm elements the peak lies
  // within 279.51-280.06 MPa and the platen-read modulus within 86.08-86.52 GPa (study
  // platens-ucs-hb-shear-energy-grid, cases/studies/platens/README.md). Here the three cheap cells
  // of that grid (5 mm particles on 10 and 5 mm elements, 2.5 mm on 5 mm; about 35 s on one
  // thread), against the grid's finest cell (1.25 mm on 2.5 mm elements: 279.51 MPa, 86.36 GPa).
  const std::vector<std::string> base{"Rock/Softening law=fracture energy",
                                      "Rock/Shear fracture energy ratio=100",
                                      "Platens/Friction coefficient=0.3", "Platens/Model=elastic"};
  const std::array<std::array<const char *, 2>, 3> cells{{{"0.005", "0.01"}, {"0.005", "0.005"}, {"0.0025", "0.005"}}};
  for (const auto &[dx, h] : cells)
  {
    std::vector<std::string> s = base;
    s.push_back(std::string("SPH/Particle spacing=") + dx);
    s.push_back(std::string("Platens/Element size=") + h);
    RunObserver   quiet;
    const Summary r = run_case(default_case("ucs/ucs.prm", s), quiet);
    std::printf("[wide steel, mu 0.3, crack band] %s m on %s m elements: %.2f MPa, E_p %.2f GPa\n", dx, h,
                r.peak_stress / 1e6, r.platen_modulus / 1e9);
    // 0.5 %: half the convergence asked of a quoted peak (measured +0.05 to +0.13 %)
    EXPECT_NEAR(r.peak_stress / 279.51e6, 1.0, 0.005) << dx << " on " << h;
    // 1 %: the convergence asked of the platen-read modulus (measured -0.15 to +0.19 %)
    EXPECT_NEAR(r.platen_modulus / 86.36e9, 1.0, 0.01) << dx << " on " << h;
    EXPECT_EQ(r.stop_reason, "post-peak drop") << dx << " on " << h;
  }
}

TEST(CoupledKinematic, AShortBondedCylinderCarriesTheFeReferencesConfinedCore)
{
  // L/D 1 between bonded rigid platens, the cases' rock perfectly plastic: the held ends confine
  // a core that carries half as much again as sigma_ci (the reference is still rising at 0.8 %
  // strain; at L/D 2 the same ends lower the peak to 268.29 MPa). The coupled curve must follow
  // the reference's through the knee and far past sigma_ci. 2.5 mm, Q2 on 8 elements per
  // radius, 80 increments (about 20 s).
  CaseParameters p     = perfectly_plastic_ucs({"Test/Length=0.05", "Platens/Bonded=true"}, true);
  p.loading.end_strain = 0.008;
  Keep rows;
  run_case(p, rows);
  const ReferenceResult r = bonded_reference(p, ReferencePlatens::rigid, 80, 0.008);
  ASSERT_TRUE(r.complete()) << r.end_reason;
  // stress at strain e, linear between rows: where the (rising) strain first reaches e
  const auto at = [](const auto &curve, const double e) {
    std::vector<double> strain, stress;
    for (const auto &row : curve)
      strain.push_back(row.strain), stress.push_back(row.stress);
    double s = std::nan("");
    EXPECT_TRUE(crossing(stress, strain, e, s)) << "the curve ends before strain " << e;
    return s;
  };
  const double sigma_ci = p.rock.hb_sigma_ci * std::pow(p.rock.hb_s, p.rock.hb_a);
  for (const double e : {0.003, 0.004, 0.0053, 0.0075})
  {
    const double coupled = at(rows.rows, e), fe = at(r.curve, e);
    std::printf("short bonded cylinder at %.4f: coupled %.2f MPa, reference %.2f MPa\n", e,
                coupled / 1e6, fe / 1e6);
    // 4 %: the coupled end layers yield a little later through the knee (measured -2.3 % at
    // 0.3 %, -1.7 % at 0.53 %, +0.00 % at 0.75 %)
    EXPECT_NEAR(coupled / fe, 1.0, 0.04) << "strain " << e;
  }
  // the confinement is the effect, not a detail: 1.54 sigma_ci at 0.75 % (measured)
  EXPECT_GT(at(r.curve, 0.0075), 1.4 * sigma_ci);
}

TEST(CoupledKinematic, ElasticPlatensOfTheSpecimensDiameterOnRollersGiveTheUniaxialClosedForm)
{
  // Steel platens as wide as the specimen, frictionless on the rock and pushed by lubricated
  // rams (Platens/Loaded face = roller): rock and steel are each in uniaxial stress, so the
  // perfectly plastic peak is the Mohr-Coulomb closed form and the frame reads the rock and the
  // two platens in series, E_p = 1 / (1 / E + 2 t / (L E_steel)) (cosim reference gives the same
  // case 282.193 MPa, the closed form). 5 mm spacing (for time).
  const CaseParameters p = kinematic_case(
    "ucs/ucs.prm", {"Platens/Model=elastic", "Platens/Diameter=0.05", "Platens/Loaded face=roller",
                    "SPH/Particle spacing=0.005", "Rock/Residual fraction=1", "Loading/End strain=0.005",
                    "Output/Snapshots=80"});
  EndFaceObserver face(p.sph.spacing, 0.5 * p.diameter);
  const Summary s = run_case(p, face);
  // 1 %: the UCS target against the closed form; measured 282.4 MPa, +0.09 %. Before an
  // unconverged closest-point iteration stopped counting as a projection (a patch sample then
  // took a face's nodes 11 mm away): 277.8, -1.6 %; before the contact points were mapped where
  // a uniform stress puts its load: 275.85, -2.2 %. The mesh's rim is a polygon inside the
  // platen's circle: before rim particles past it kept their contact the run gave 215.6 MPa
  // (2.5 mm: 216.7), its rim failing at 108 MPa
  EXPECT_NEAR(s.peak_stress / closed_form_ucs(), 1.0, 0.01);
  // nothing fails far below the strength (measured: the first failure at 0.97 of it; with the
  // unsupported rim at 0.38). 0.8: the end layer's unevenness, with margin
  EXPECT_GT(extra(s, "failure_onset_stress_MPa") * 1e6, 0.8 * closed_form_ucs());
  const double series =
    1.0 / (1.0 / s.youngs_modulus + 2.0 * p.platens.thickness / (p.length * p.platens.steel.youngs_modulus));
  // 2.5 %: measured -1.78 % at 5 mm (2.5 mm, body-fitted: -0.42 %), the platens' octagon at
  // 5 mm (its area 10 % below the circle's) carrying the rock's load
  EXPECT_NEAR(s.platen_modulus / series, 1.0, 0.025);
  // 1 %: the interface's energy target; measured 0.86 %
  EXPECT_LT(s.energy_balance_error, 0.01);
  // the end face at half the peak against cosim reference's (uniform: 282.193 MPa, its closed
  // form): 5 % RMS, as with bonded ends; measured 0.82 % (2.6 % before the contact points were
  // mapped; at 2.5 mm a rim left without contact loaded the ring inside it 6 % above the mean)
  ReferenceOptions o;
  o.interface = ReferenceInterface::free_slip;
  o.platens   = ReferencePlatens::elastic;
  o.n_radial  = 4;
  const ReferenceResult r = run_reference_cylinder(p, o);
  const double rms        = end_face_rms(face, s.peak_stress, r, 0.5 * p.diameter);
  std::cout << "[rollers] reference " << r.peak_stress / 1e6 << " MPa; end face at half the peak: RMS " << rms << "\n";
  // the reference on rollers is uniform, so its limit load is the closed form (measured 282.193
  // against 282.193 MPa); 1e-4: the limit-load detection's force tolerance (1e-7) and the last
  // increment's size, with margin
  EXPECT_NEAR(r.peak_stress / closed_form_ucs(), 1.0, 1e-4);
  EXPECT_LT(rms, 0.05);
}

TEST(CoupledKinematic, ASofteningRockOnElasticPlatensOfItsDiameterReachesTheClosedForm)
{
  // The same test with the default strain-softening rock, whose end layer fails at the first
  // particle the steel loads unevenly (Mohr-Coulomb's N = (1 + sin phi) / (1 - sin phi) = 18.3 at
  // phi 63.7 deg turns 1 % of lateral tension into 18 % less strength): the steel face must stay
  // flat to a small fraction of a micrometre under the end layer. The specimen is body-fitted (its side round, no
  // staircase), 2.5 mm. Before the contact points were mapped (ContactParameters::face_radius_mapped,
  // rim_angles) and the patches sampled at 4 x 4 points, the same run gave 261.9 MPa (lattice)
  // and 262.5 (body-fitted), the first failure in the end layer at 0.69 of the strength.
  const CaseParameters p = kinematic_case(
    "ucs/ucs.prm", {"Platens/Model=elastic", "Platens/Diameter=0.05", "Platens/Loaded face=roller",
                    "SPH/Particle arrangement=body-fitted", "Loading/End strain=0.005"});
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  std::cout << "[rollers, softening] peak " << s.peak_stress / 1e6 << " MPa, first failure "
            << extra(s, "failure_onset_stress_MPa") << " MPa, platen modulus " << s.platen_modulus / 1e9 << " GPa\n";
  // 1 %: the UCS target against the closed form (rigid platens give 282.9 MPa on this
  // rock, +0.25 %); measured 282.42 MPa, +0.08 %
  EXPECT_NEAR(s.peak_stress / closed_form_ucs(), 1.0, 0.01);
  // the first failure near the strength, not in the end layer at 0.7 of it: 0.85 (measured
  // 0.93)
  EXPECT_GT(extra(s, "failure_onset_stress_MPa") * 1e6, 0.85 * closed_form_ucs());
  const double series =
    1.0 / (1.0 / s.youngs_modulus + 2.0 * p.platens.thickness / (p.length * p.platens.steel.youngs_modulus));
  // 1 %: the interface's modulus target; measured -0.4 %
  EXPECT_NEAR(s.platen_modulus / series, 1.0, 0.01);
}

namespace
{
  /// A numerical parameter of the interface kept to the interface's targets: `key` at each of
  /// `values` moves the UCS peak by less than 0.5 % and the platen-read modulus by less than 1 %
  /// against `key` at `base` (the rest of the case from `settings`).
  void expect_result_kept(const std::vector<std::string> &settings, const std::string &key,
                          const std::string &base, const std::vector<std::string> &values)
  {
    auto run = [&](const std::string &value) {
      std::vector<std::string> s = settings;
      s.push_back(key + "=" + value);
      RunObserver quiet;
      return run_case(kinematic_case("ucs/ucs.prm", s), quiet);
    };
    const Summary b = run(base);
    for (const std::string &v : values)
    {
      SCOPED_TRACE(key + "=" + v);
      const Summary s = run(v);
      std::cout << "[" << key << " " << v << "] peak " << s.peak_stress / 1e6 << " MPa (" << base << ": "
                << b.peak_stress / 1e6 << "), platen modulus " << s.platen_modulus / 1e9 << " GPa (" << base
                << ": " << b.platen_modulus / 1e9 << ")\n";
      EXPECT_NEAR(s.peak_stress / b.peak_stress, 1.0, 0.005);
      EXPECT_NEAR(s.platen_modulus / b.platen_modulus, 1.0, 0.01);
    }
  }
} // namespace

TEST(CoupledKinematic, TheJointSolutionsToleranceTimesAndOverFourKeepsTheResult)
{
  // the kinematic interface has no stiffness; one numerical constant is the tolerance of the
  // joint solution on a deformable face (Platens/Contact tolerance, 1e-6 of the contact radius;
  // the patch points, its other setting, in the next test).
  // UCS on elastic platens at 5 mm (for time), the tolerance x4 and /4: the peak must move by
  // less than 0.5 % and the platen-read modulus by less than 1 % (the interface's targets;
  // measured on 60 mm platens 0.019 % and 0.006 %)
  expect_result_kept({"Platens/Model=elastic", "SPH/Particle spacing=0.005"}, "Platens/Contact tolerance", "1e-6",
                     {"4e-6", "2.5e-7"});
}

TEST(CoupledKinematic, TheContactPatchIsConvergedAtItsDefaultPoints)
{
  // Platens/Contact patch points: a particle's load spread over its end-face patch, sampled at
  // N x N points (4 on cylinder platens). The softening rock on elastic platens of its diameter
  // (the case that needs the patch), body-fitted, at 5 mm (for time): N x 4 = 16 and N / 2 = 2
  // must move the peak by less than 0.5 % and the platen-read modulus by less than 1 % (the
  // interface's targets; measured 280.93 / 281.41 / 281.42 MPa at 2 / 4 / 16, -0.17 % and
  // +0.002 %; the modulus 80.052 GPa within 0.01 %). N = 1 is no patch but a point load, which
  // aliases against the mesh (2.5 mm, cases/studies/platens/README.md: 272.3 against 283.0
  // MPa): the patch is part of the formulation, as the loaded-face correction is, and is not
  // varied below 2.
  expect_result_kept({"Platens/Model=elastic", "Platens/Diameter=0.05", "Platens/Loaded face=roller",
                      "SPH/Particle arrangement=body-fitted", "SPH/Particle spacing=0.005", "Loading/End strain=0.005"},
                     "Platens/Contact patch points", "4", {"2", "16"});
}

TEST(CoupledKinematic, PlatenElementsHalfTheSpacingStayStable)
{
  // Face nodes lighter than the particle (5 mm particles on 2.5 mm elements: a node carries a
  // sixth of a particle's mass) follow the distance the particle is held at, r (n . F n). Taken
  // from the step before, that distance moved with the particle's own position a step late
  // (by half the particle's own move at a lattice face) and the end layer and the face rang up:
  // an elastic rock reached a kinetic energy of 1.1e-2 of its internal energy by a strain of
  // 0.003 and "failed" at 259.8 MPa. Held at the step's end (ContactParticles::self_gradient)
  // it stays quasi-static.
  // (`cosim` still refuses elements finer than the particles: stable, their end layer fails
  // early, app/src/case_file.cc; the test sets them past the case reader.)
  CaseParameters p = kinematic_case(
    "ucs/ucs.prm", {"Platens/Model=elastic", "Platens/Diameter=0.05", "Platens/Loaded face=roller",
                    "SPH/Particle arrangement=body-fitted", "SPH/Particle spacing=0.005",
                    "Rock/Model=elastic", "Loading/End strain=0.003"});
  p.platens.element_size_from_spacing = false;
  p.platens.steel.element_size        = 0.0025;
  RunObserver quiet;
  const Summary s = run_case(p, quiet);
  std::cout << "[elements of half the spacing] kinetic / internal " << s.max_kinetic_to_internal_energy
            << ", platen modulus " << s.platen_modulus / 1e9 << " GPa, energy balance " << s.energy_balance_error
            << "\n";
  EXPECT_EQ(s.stop_reason, "end strain");
  // measured 5.6e-6; 1e-4 is the order of the quasi-static runs' (1.4e-5 for the softening rock
  // on these elements), a hundredth of the unstable run's
  EXPECT_LT(s.max_kinetic_to_internal_energy, 1e-4);
  const double series =
    1.0 / (1.0 / s.youngs_modulus + 2.0 * p.platens.thickness / (p.length * p.platens.steel.youngs_modulus));
  // 1 %: the interface's modulus target; measured 81.26 GPa
  EXPECT_NEAR(s.platen_modulus / series, 1.0, 0.01);
  // 1 %: the interface's energy target; measured 0.49 %
  EXPECT_LT(s.energy_balance_error, 0.01);
}

namespace
{
  /// EndFaceObserver that also keeps the first local maximum of the stress past 0.9 of `near`
  /// [Pa]: the yield plateau's onset, before the growing section (large dilation) raises the
  /// nominal stress again.
  class FirstPeakObserver : public EndFaceObserver
  {
  public:
    FirstPeakObserver(const double spacing, const double radius, const double near)
        : EndFaceObserver(spacing, radius)
        , near_(near)
    {}
    double first_peak = 0;
    void history(const HistoryRow &row) override
    {
      if (first_peak == 0 && last_ > 0.9 * near_ && row.stress < last_)
        first_peak = last_;
      last_ = row.stress;
    }

  private:
    double near_, last_ = 0;
  };
} // namespace

TEST(CoupledKinematic, WideElasticFreeSlipPlatensGiveTheFeReferenceWithAssociatedFlow)
{
  // The default steel platens (1.2 D wide, clamped), frictionless, against cosim reference's
  // solution of the same, perfectly plastic rock with associated flow (psi = phi): the problem
  // is well posed there (the case's psi = 0 is not: neither solver converges,
  // ReferenceCylinder.WideElasticFreeSlipPlatensConvergeOnlyWithAssociatedFlow), and the
  // reference's limit load is the closed form on every mesh. Body-fitted, 5 mm (for time),
  // loaded over 160 transit times: the dilation's onset is dynamic (40 transits: 290.6 MPa).
  CaseParameters p = kinematic_case(
    "ucs/ucs.prm", {"Platens/Model=elastic", "SPH/Particle arrangement=body-fitted", "SPH/Particle spacing=0.005",
                    "Rock/Residual fraction=1", "Loading/Transit times=160", "Loading/End strain=0.0038",
                    "Output/Snapshots=80"});
  p.rock.dilation_angle = p.rock.friction_angle;
  FirstPeakObserver run(p.sph.spacing, 0.5 * p.diameter, closed_form_ucs());
  run_case(p, run);
  ReferenceOptions o;
  o.interface    = ReferenceInterface::free_slip;
  o.platens      = ReferencePlatens::elastic;
  o.n_radial     = 4;
  o.n_increments = 60;
  o.end_strain   = 0.006;
  const ReferenceResult r = run_reference_cylinder(p, o);
  const double rms        = end_face_rms(run, run.first_peak, r, 0.5 * p.diameter);
  std::cout << "[wide, associated] coupled " << run.first_peak / 1e6 << " MPa, reference " << r.peak_stress / 1e6
            << " MPa; end face at half the peak: RMS " << rms << "\n";
  // 2 %: the interface's target against the reference; measured 284.70 MPa against 282.19
  // (+0.9 %; 2.5 mm: 284.89)
  EXPECT_NEAR(run.first_peak / r.peak_stress, 1.0, 0.02);
  // 5 % RMS over the face at half the peak (elastic there: the steel dishes under the rock), the
  // interface's target, as for bonded ends; measured 0.68 %
  EXPECT_LT(rms, 0.05);
}

// Platens whose friction holds the end faces confine a short cylinder's end zones and stiffen what
// the frame reads (diagnose's end-friction model and the discovery generator take this
// stiffening): elastic M1 rock (nu 0.28), L/D 1/2 (50 x 25 mm), rigid platens, the platen-read
// modulus with mu 1 over that with free slip against the FE reference's bonded cylinder (Q2, 8
// elements per radius; 16 move it by 5e-5 at nu 0.25).
TEST(CoupledKinematic, FrictionHeldEndsStiffenAShortCylinderAsTheFeReferenceSays)
{
  const std::vector<std::string> short_elastic{"Rock/Model=elastic", "Loading/End strain=0.001",
                                               "Test/Length=0.025"};
  const auto modulus = [&](const std::string &spacing, const std::string &friction) {
    std::vector<std::string> s = short_elastic;
    s.push_back("SPH/Particle spacing=" + spacing);
    s.push_back("Platens/Friction coefficient=" + friction);
    RunObserver quiet;
    return run_case(kinematic_case("ucs/ucs.prm", s), quiet).platen_modulus;
  };
  ReferenceOptions o;
  o.interface             = ReferenceInterface::bonded;
  o.n_increments          = 1;
  o.end_strain            = 0.001;
  const CaseParameters p  = kinematic_case("ucs/ucs.prm", short_elastic);
  const ReferenceResult r = run_reference_cylinder(p, o);
  const double fe = r.curve.back().stress / r.curve.back().strain / p.rock.youngs_modulus;
  const double coarse = modulus("0.0025", "1") / modulus("0.0025", "0");
  const double held   = modulus("0.0025", "0.3") / modulus("0.0025", "0");
  const double fine   = modulus("0.00125", "1") / modulus("0.00125", "0");
  std::printf("held ends, L/D 1/2: FE %.5f; coupled %.5f / %.5f at 2.5 / 1.25 mm; mu 0.3 %.5f\n",
              fe, coarse, fine, held);
  // the effect itself is large: the reference's held ends stiffen the specimen by 10 % (measured
  // 1.10155); free slip would read 1
  EXPECT_GT(fe, 1.05);
  // 1 % at 1.25 mm: the interface's modulus target (measured 1.11103, +0.86 %; 2.5 mm: 1.12295,
  // +1.9 %)
  EXPECT_NEAR(fine / fe, 1.0, 0.01);
  // and the error falls with the spacing (an end zone resolved by more particle rows): measured
  // 0.44 of it, about first order; 0.6 leaves room
  EXPECT_LT(std::abs(fine - fe), 0.6 * std::abs(coarse - fe));
  // friction of 0.3 holds the faces nearly as much as 1 (the rim slips a little): measured
  // 0.990 of it at 2.5 mm; 2 % is a fifth of the effect
  EXPECT_NEAR(held / coarse, 1.0, 0.02);
}
