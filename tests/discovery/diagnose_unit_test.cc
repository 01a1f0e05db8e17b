// Unit tests of the pieces of `cosim diagnose`: the data readers (bad rows -> InputError naming
// file and line), the surrogate's envelopes against the rock models' own return mappings in
// sph/rock_models.h (a stress on the envelope is admissible just inside and returned just outside),
// and the closure / Weibull / rate laws added to rock_models.h.
#include "../../diagnose/src/diagnose_model.h"
#include "held_ends.h"

#include <diagnose/diagnose.h>
#include <coupling/run_case.h>
#include <sph/rock_models.h>

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

namespace
{
  using namespace diagnose;
  namespace fs = std::filesystem;

  std::string folder(const std::string &name)
  {
    const std::string d = std::string(COSIM_BINARY_DIR) + "/diagnose-unit/" + name;
    fs::remove_all(d);
    fs::create_directories(d);
    return d;
  }

  void write(const std::string &path, const std::string &text)
  {
    std::ofstream(path) << text;
  }

  std::string error_of(const std::string &dir)
  {
    try
    {
      read_data(dir);
    }
    catch (const coupling::InputError &e)
    {
      return e.what();
    }
    return "";
  }

  /// True when the rock model leaves `s` (principal, tension +) unchanged under a zero increment.
  bool admissible(const sph::rock::Principal &s, const sph::MaterialParameters &m)
  {
    const auto p   = sph::rock::make_model_constants(m);
    sph::Tensor3 S = sph::Tensor3::Zero();
    for (int i = 0; i < 3; ++i)
      S(i, i) = s[i];
    sph::MaterialState h;
    const auto u = m.model == sph::RockModel::hoek_brown
                     ? sph::rock::update_hoek_brown(S, sph::Tensor3::Zero(), h, p)
                     : sph::rock::update_mohr_coulomb(S, sph::Tensor3::Zero(), h, p);
    return (u.stress - S).norm() < 1e-9 * S.norm();
  }
} // namespace

TEST(DiagnoseData, ReadsAFolder)
{
  const auto d = folder("good");
  write(d + "/material.csv",
        "group,E_GPa,nu,density_kg_m3,UCS_MPa,BTS_MPa,c_MPa,phi_deg\nA,60,0.25,,150,10,,\n");
  write(d + "/strength.csv",
        "test,group,sigma1_MPa,sigma3_MPa\nUCS,A,150,0\nBTS,A,0,-10\nCTCS,A,300,20\n");
  fs::create_directories(d + "/curves");
  write(d + "/curves/x.csv",
        "# test: UCS\n# group: A\n# diameter_mm: 50\n# length_mm: 100\n# displacement: platen\n"
        "time_s,displacement_mm,force_kN\n0,0,0\n1,0.1,50\n2,0.2,100\n3,0.3,150\n4,0.31,120\n");
  const Data data = read_data(d);
  ASSERT_EQ(data.materials.size(), 1u);
  EXPECT_FALSE(data.materials[0].c_MPa.has_value());
  ASSERT_EQ(data.strengths.size(), 3u);
  EXPECT_EQ(data.strengths[1].sigma3, -10);
  ASSERT_EQ(data.curves.size(), 1u);
  EXPECT_EQ(data.curves[0].force.size(), 5u);
  EXPECT_TRUE(data.curves[0].platen_displacement);
}

TEST(DiagnoseData, BadRowsNameFileAndLine)
{
  auto d = folder("bad1");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCS,A,150,0\nBTS,A,10,-10\n");
  EXPECT_NE(error_of(d).find("strength.csv:3"), std::string::npos) << error_of(d);
  d = folder("bad2");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCX,A,150,0\n");
  EXPECT_NE(error_of(d).find("strength.csv:2"), std::string::npos) << error_of(d);
  d = folder("bad3");
  write(d + "/material.csv", "group,E_GPa,phi_deg,c_MPa\nA,60,95,10\n");
  EXPECT_NE(error_of(d).find("material.csv:2"), std::string::npos) << error_of(d);
  d = folder("bad4");
  fs::create_directories(d + "/curves");
  write(d + "/curves/x.csv",
        "# test: UCS\n# group: A\n# diameter_mm: 50\n# length_mm: 100\n# displacement: frame\n"
        "time_s,displacement_mm,force_kN\n0,0,0\n");
  EXPECT_NE(error_of(d).find("displacement"), std::string::npos) << error_of(d);
  d = folder("empty");
  EXPECT_NE(error_of(d).find("no material.csv"), std::string::npos) << error_of(d);
}

TEST(DiagnoseSurrogate, EnvelopesLieOnTheRockModelsSurfaces)
{
  // an envelope point is admissible at 0.999 of its deviator and returned at 1.001 (tolerance:
  // 0.1 % either side of the surface, far above the models' 1e-12 return tolerance)
  GroupBase g{"A", 150.0, 40.0, 60e3, ""};
  const std::vector<GroupBase> groups{g};
  for (const std::string effect : {"", "tension_cutoff", "envelope_curvature"})
  {
    EffectSet e;
    if (!effect.empty())
      e.insert(effect);
    const Surrogate s(groups, e, true);
    std::vector<double> p = s.initial();
    sph::MaterialParameters m;
    const double sphi = std::sin(40.0 * M_PI / 180), cphi = std::cos(40.0 * M_PI / 180);
    m.model            = effect == "tension_cutoff" ? sph::RockModel::mohr_coulomb_cutoff
                                                    : sph::RockModel::mohr_coulomb;
    m.cohesion         = 150e6 * (1 - sphi) / (2 * cphi);
    m.friction_angle   = 40.0 * M_PI / 180;
    m.tensile_strength = effect == "tension_cutoff" ? 0.04 * 150e6 : 0;
    if (effect == "envelope_curvature")
    {
      m.model       = sph::RockModel::hoek_brown;
      m.hb_sigma_ci = 150e6;
      m.hb_mb       = 15.0;
    }
    for (double s3 : {0.0, 10.0, 30.0})
    {
      const double s1 = s.envelope("A", s3, p);
      for (double f : {0.999, 1.001})
      {
        const double q = (s1 - s3) * f;
        const sph::rock::Principal st(-s3 * 1e6, -s3 * 1e6, -(s3 + q) * 1e6);
        EXPECT_EQ(admissible(st, m), f < 1) << effect << " s3 " << s3 << " f " << f;
      }
    }
    const double T = s.tensile_strength("A", p);
    for (double f : {0.999, 1.001})
      EXPECT_EQ(admissible(sph::rock::Principal(T * f * 1e6, 0, 0), m), f < 1)
        << effect << " tension f " << f;
  }
}

// The surrogate's end zone of friction-held ends (a law fitted to the deal.II reference at L/D 1)
// against the generator's Ritz solution of the held elastic cylinder, written apart from it:
// L/D 1/2 to 2.5, nu 0.1-0.4 (measured law / Ritz 0.955-1.006). 3 % (5 % at L/D 1/2, where the
// Ritz c is up to 4.5 % above its L/D >= 1 value at nu 0.4): the law does not follow L/D; 3 % of
// c at nu 0.25 is 0.2 % of a short specimen's displacement, one noise SD of the generator's
// curves.
TEST(DiagnoseSurrogate, HeldEndShorteningAgreesWithAnElasticRitzSolution)
{
  for (const double nu : {0.1, 0.25, 0.4})
    for (const double slenderness : {0.5, 1.0, 2.0, 2.5})
    {
      const double ritz = discovery::held_shortening(slenderness, nu);
      EXPECT_NEAR(held_end_shortening(nu) / ritz, 1.0, slenderness < 1 ? 0.05 : 0.03)
        << "nu " << nu << ", L/D " << slenderness;
    }
  // the Ritz solution against the deal.II reference's E_app / E at nu 0.25 (mesh 16): 1.07719 /
  // 1.03646 / 1.01777 at L/D 1/2, 1, 2; a Ritz solution is stiffer, within 1e-4 here
  EXPECT_NEAR(discovery::held_stiffening(0.5, 0.25), 1.07719, 2e-4);
  EXPECT_NEAR(discovery::held_stiffening(1.0, 0.25), 1.03646, 2e-4);
  EXPECT_NEAR(discovery::held_stiffening(2.0, 0.25), 1.01777, 2e-4);
}

TEST(RockExtensions, CrackClosureStrainIsTheIntegralOfTheTangentCompliance)
{
  const double E = 60e9, E0 = 20e9, scc = 15e6;
  double eps  = 0;
  const int n = 20000;
  for (int i = 0; i < n; ++i)
  {
    const double a = 5e6 + 100e6 * i / n, b = 5e6 + 100e6 * (i + 1) / n;
    eps += 0.5 *
           (1 / sph::rock::crack_closure_tangent_modulus(a, E, E0, scc) +
            1 / sph::rock::crack_closure_tangent_modulus(b, E, E0, scc)) *
           (b - a);
  }
  // trapezoidal error ~ (h^2/12) max|f''| * range: below 1e-8 relative at n = 20000
  EXPECT_NEAR(sph::rock::crack_closure_strain(5e6, 105e6, E, E0, scc), eps, 1e-8 * eps);
  EXPECT_DOUBLE_EQ(sph::rock::crack_closure_tangent_modulus(0, E, E0, scc), E0);
  EXPECT_NEAR(sph::rock::crack_closure_tangent_modulus(1e9, E, E0, scc), E, 1e-6 * E);
}

TEST(RockExtensions, WeibullWeakestLinkAndScatter)
{
  // Monte Carlo with the per-particle law: the mean of the weakest of N particles scales as
  // N^(-1/m), and the particle CV matches the closed form. 20000 samples: sampling error of a mean
  // of a CV ~0.1-0.2 quantity ~0.15 %; tolerance 2 %.
  const double m = 8;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0, 1);
  auto weakest_mean = [&](int N) {
    double s = 0;
    for (int k = 0; k < 20000; ++k)
    {
      double w = 1e300;
      for (int i = 0; i < N; ++i)
        w = std::min(w, sph::rock::weibull_strength_factor(u(rng), m));
      s += w;
    }
    return s / 20000;
  };
  EXPECT_NEAR(weakest_mean(80) / weakest_mean(10), sph::rock::weakest_link_strength_factor(8.0, m),
              0.02);
  double s = 0, s2 = 0;
  for (int k = 0; k < 20000; ++k)
  {
    const double x = sph::rock::weibull_strength_factor(u(rng), m);
    s += x;
    s2 += x * x;
  }
  const double mean = s / 20000, cv = std::sqrt(s2 / 20000 - mean * mean) / mean;
  EXPECT_NEAR(mean, 1.0, 0.01);
  EXPECT_NEAR(cv, sph::rock::weibull_coefficient_of_variation(m), 0.02 * cv);
}

TEST(RockExtensions, RateFactorPerDecade)
{
  EXPECT_DOUBLE_EQ(sph::rock::rate_strength_factor(1e-5, 1e-5, 0.05), 1.0);
  EXPECT_NEAR(sph::rock::rate_strength_factor(1e-3, 1e-5, 0.05), 1.10, 1e-12);
}

namespace
{
  /// A UCS curve file of group A (50 x 100 mm, platen displacement): the header plus `rows`.
  std::string ucs_curve(const std::string &rows, const std::string &extra_header = "")
  {
    return "# test: UCS\n# group: A\n# diameter_mm: 50\n# length_mm: 100\n# displacement: specimen\n" +
           extra_header + "time_s,displacement_mm,force_kN\n" + rows;
  }

  /// Pre-peak rows of a linear curve with E = 60 GPa (A = 1963.5 mm^2, L = 100 mm) up to the
  /// force `top` [kN], then (with `failure`) a drop.
  std::string linear_rows(const double top, const bool failure)
  {
    std::string s;
    const double area = M_PI * 25 * 25;
    for (int i = 0; i <= 10; ++i)
    {
      const double f = top * i / 10.0, d = f * 1e3 / area / 60e3 * 100;
      s += std::to_string(i) + "," + std::to_string(d) + "," + std::to_string(f) + "\n";
    }
    if (failure)
      s += "11," + std::to_string(top * 1e3 / M_PI / 625 / 60e3 * 100 * 1.05) + "," +
           std::to_string(0.5 * top) + "\n";
    return s;
  }
} // namespace

// Triaxial extension: sigma1 = sigma2 is the confining fluid's pressure and sigma3 the axial
// stress, which may be tensile (tensile and hybrid tensile-shear fractures): accepted, and it
// informs the tensile side. Refused only what cannot be: a fluid that pulls (sigma1 < 0 in TXE,
// sigma3 < 0 in CTCS) or sigma1 <= sigma3 (not the major principal stress).
TEST(DiagnoseData, TensileTxeRowsAreAcceptedAndImpossibleOnesRefused)
{
  auto d = folder("txe-hybrid");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCS,A,150,0\nUCS,A,155,0\n"
                             "TXE,A,40,-5\nTXE,A,20,-8\nTXE,A,300,40\nCTCS,A,300,20\n");
  EXPECT_EQ(error_of(d), "");
  const Data data = read_data(d);
  ASSERT_EQ(data.strengths.size(), 6u);
  EXPECT_EQ(data.strengths[3].sigma3, -8);
  // the study runs on them: the tensile TXE rows give the tension cut-off the tensile side it
  // needs (no BTS here), so it is a candidate, not "not applicable"
  const Diagnosis g = diagnose::diagnose(data, Options{});
  EXPECT_EQ(g.n_strength, 6);
  bool cutoff_candidate = false;
  for (const auto &c : g.candidates)
    cutoff_candidate = cutoff_candidate || c.name == "tension_cutoff";
  EXPECT_TRUE(cutoff_candidate);

  d = folder("txe-fluid-pulls");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCS,A,150,0\nTXE,A,-2,-8\n");
  EXPECT_NE(error_of(d).find("strength.csv:3"), std::string::npos) << error_of(d);
  EXPECT_NE(error_of(d).find("fluid cannot pull"), std::string::npos) << error_of(d);
  d = folder("txe-unordered");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nTXE,A,10,12\n");
  EXPECT_NE(error_of(d).find("sigma1_MPa > sigma3_MPa"), std::string::npos) << error_of(d);
  d = folder("ctcs-tensile-confinement");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nCTCS,A,100,-5\n");
  EXPECT_NE(error_of(d).find("a CTCS row needs sigma3_MPa >= 0"), std::string::npos) << error_of(d);
}

// A specimen with only its peak (a curve file of fewer than 5 rows) gives a strength and no curve
// points; a specimen with only a curve (header 'failure: no': stopped before failure) gives curve
// points and no strength, and a group measured that way alone is diagnosed for its stiffness.
TEST(DiagnoseData, PeakOnlyAndCurveOnlySpecimensAreAccepted)
{
  auto d = folder("peak-only");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCS,A,150,0\nBTS,A,0,-10\n");
  fs::create_directories(d + "/curves");
  write(d + "/curves/peak.csv", ucs_curve("10,0.25,300\n"));
  EXPECT_EQ(error_of(d), "");
  Diagnosis g = diagnose::diagnose(read_data(d), Options{});
  EXPECT_EQ(g.n_strength, 3); // two rows and the peak
  EXPECT_EQ(g.n_curve_points, 0);

  d = folder("curve-only");
  write(d + "/strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCS,A,150,0\nBTS,A,0,-10\n");
  fs::create_directories(d + "/curves");
  write(d + "/curves/modulus.csv", ucs_curve(linear_rows(100, false), "# failure: no\n"));
  EXPECT_EQ(error_of(d), "");
  g = diagnose::diagnose(read_data(d), Options{});
  EXPECT_EQ(g.n_strength, 2); // the curve's largest force (100 kN, 51 MPa) is no strength
  EXPECT_GT(g.n_curve_points, 5);

  d = folder("stiffness-only-group");
  fs::create_directories(d + "/curves");
  write(d + "/curves/a.csv", ucs_curve(linear_rows(100, false), "# failure: no\n"));
  write(d + "/curves/b.csv", ucs_curve(linear_rows(120, false), "# failure: no\n"));
  EXPECT_EQ(error_of(d), "");
  g = diagnose::diagnose(read_data(d), Options{});
  EXPECT_EQ(g.n_strength, 0);
  EXPECT_GT(g.n_curve_points, 10);
  // the baseline's E is the curves' own (60 GPa): it explains them to their noise
  EXPECT_LT(g.baseline.fit, 1.0);

  // what cannot be: no rows at all, a curve without failure too short to be a curve, an
  // unknown failure flag
  d = folder("no-rows");
  fs::create_directories(d + "/curves");
  write(d + "/curves/x.csv", ucs_curve(""));
  EXPECT_NE(error_of(d).find("no rows"), std::string::npos) << error_of(d);
  d = folder("short-curve-only");
  fs::create_directories(d + "/curves");
  write(d + "/curves/x.csv", ucs_curve("0,0,0\n1,0.1,50\n", "# failure: no\n"));
  EXPECT_NE(error_of(d).find("at least 5 rows"), std::string::npos) << error_of(d);
  d = folder("failure-maybe");
  fs::create_directories(d + "/curves");
  write(d + "/curves/x.csv", ucs_curve(linear_rows(100, true), "# failure: maybe\n"));
  EXPECT_NE(error_of(d).find("accepted: yes"), std::string::npos) << error_of(d);
}
