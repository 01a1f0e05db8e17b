// The CSV reader, the material table and Eqs. 14-15 against the paper's tables.
#include <diagnose/calibrate.h>
#include <diagnose/csv.h>
#include <diagnose/material_table.h>
#include <app/paths.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <sstream>

using diagnose::CsvTable;

namespace
{
  std::string two_decimals(double v)
  {
    char b[32];
    std::snprintf(b, sizeof b, "%.2f", v);
    return b;
  }

  /// The message of the InputError that `f` throws ("" if none).
  template <typename F>
  std::string input_error(F f)
  {
    try
    {
      f();
    }
    catch (const coupling::InputError &e)
    {
      return e.what();
    }
    return "";
  }
} // namespace

TEST(Csv, CommentsHeaderRowsAndEmptyCells)
{
  std::istringstream in("# Table X: test\n#second\n\na, b ,c\n1,,\"x,y\"\n 2.5 , 3 ,z\n");
  const auto t = CsvTable::parse(in, "t.csv");
  ASSERT_EQ(t.comments().size(), 2u);
  EXPECT_EQ(t.comments()[0], "Table X: test");
  ASSERT_EQ(t.columns().size(), 3u);
  EXPECT_EQ(t.columns()[1], "b");
  ASSERT_EQ(t.n_rows(), 2u);
  EXPECT_EQ(t.line(0), 5u);
  EXPECT_EQ(t.where(1), "t.csv:6");
  EXPECT_FALSE(t.optional_number(0, "b").has_value());
  EXPECT_EQ(t.text(0, "c"), "x,y");
  EXPECT_NEAR(t.number(1, "a"), 2.5, 1e-15);
  EXPECT_NEAR(*t.optional_number(1, "b"), 3.0, 1e-15);
}

TEST(Csv, WrongCellCountNamesTheLine)
{
  std::istringstream in("# c\na,b\n1,2\n1,2,3\n");
  const std::string m = input_error([&] { CsvTable::parse(in, "t.csv"); });
  EXPECT_NE(m.find("t.csv:4"), std::string::npos) << m;
  EXPECT_NE(m.find("3 cells"), std::string::npos) << m;
}

TEST(Csv, NanInfAndTextAreNotNumbers)
{
  std::istringstream in("a,b\nnan,inf\nabc,1e400\n");
  const auto t = CsvTable::parse(in, "t.csv");
  for (std::size_t row = 0; row < 2; ++row)
    for (const auto *col : {"a", "b"})
    {
      const std::string m = input_error([&] { t.number(row, col); });
      EXPECT_NE(m.find("t.csv:" + std::to_string(row + 2)), std::string::npos) << m;
      EXPECT_NE(m.find("not a finite number"), std::string::npos) << m;
    }
}

TEST(Csv, EmptyRequiredCellAndMissingColumn)
{
  std::istringstream in("a,b\n,1\n");
  const auto t = CsvTable::parse(in, "t.csv");
  EXPECT_NE(input_error([&] { t.number(0, "a"); }).find("t.csv:2"), std::string::npos);
  EXPECT_NE(input_error([&] { t.require_columns({"a", "zz"}); }).find("no column 'zz'"), std::string::npos);
}

TEST(Csv, NoHeaderAndUnterminatedQuote)
{
  std::istringstream empty("# only a comment\n");
  EXPECT_NE(input_error([&] { CsvTable::parse(empty, "e.csv"); }).find("no header"), std::string::npos);
  std::istringstream quote("a\n\"open\n");
  EXPECT_NE(input_error([&] { CsvTable::parse(quote, "q.csv"); }).find("q.csv:2"), std::string::npos);
}

TEST(Csv, EveryDataTableHasItsHeaderAndReads)
{
  for (const auto *f : {"table1_test_design.csv", "table2_regressions.csv", "table3_fitted_parameters.csv",
                        "table4_calibrated.csv", "table5_ucs_results.csv", "table6_bts_results.csv"})
  {
    const auto t = CsvTable::read(app::data_directory().string() + "/" + f);
    ASSERT_FALSE(t.comments().empty()) << f;
    EXPECT_EQ(t.comments()[0].rfind("Yang et al. 2022, Table", 0), 0u) << f;
    EXPECT_GT(t.n_rows(), 9u) << f;
  }
}

TEST(MaterialTable, GroupsOfThePaper)
{
  const auto table = diagnose::MaterialTable::read(app::data_directory().string());
  ASSERT_EQ(table.groups().size(), 10u);
  const auto &m1 = table.find("M1");
  EXPECT_NEAR(m1.youngs_modulus, 97.07e9, 1e-3);
  EXPECT_NEAR(m1.bts, 15.43e6, 1e-6); // Table 3 (Table 6 prints 15.60, see cases/data/README.md)
  EXPECT_FALSE(m1.measured_cohesion.has_value());
  EXPECT_EQ(table.groups_with_measured_strength(), "M8, M9, M10");
  EXPECT_NEAR(*table.find("M10").calibrated_friction_angle, 67.72, 1e-12);
  EXPECT_THROW(table.find("M11"), coupling::InputError);
}

// Table 4 from Table 3's UCS and BTS, to Table 4's printed precision (0.01 MPa, 0.01 deg). All
// ten groups reproduce; M1 only with Table 3's BTS 15.43 MPa (Table 6's 15.60 would give
// c = 33.17 MPa, phi = 63.54 deg), see cases/data/README.md.
TEST(Calibrate, ReproducesTable4)
{
  const auto table = diagnose::MaterialTable::read(app::data_directory().string());
  for (const auto &g : table.groups())
  {
    const auto s = diagnose::calibrate_mohr_coulomb(g.ucs / 1e6, g.bts / 1e6);
    ASSERT_TRUE(g.calibrated_cohesion.has_value()) << g.group;
    EXPECT_EQ(two_decimals(s.cohesion), two_decimals(*g.calibrated_cohesion / 1e6)) << g.group;
    EXPECT_EQ(two_decimals(s.friction_angle), two_decimals(*g.calibrated_friction_angle)) << g.group;
  }
}

// simulator_calibrated.csv: every group has the simulator's c, phi, and they are Mohr-Coulomb
// rocks of the group's UCS: their closed form 2 c cos(phi) / (1 - sin(phi)) within 0.5 % of
// Table 3's (measured 0.19-0.25 % below: the calibration ran the body-fitted cylinder at 2.5 mm,
// whose peak lies that much above the closed form), and phi below Table 4's (the converged disc
// asks for less friction than Eq. 15's uniaxial tension: 1.7-3.2 deg), so a copy of Table 4 or a
// column swapped would fail it.
TEST(MaterialTable, SimulatorCalibratedRocksHaveTheGroupsUcs)
{
  const auto table = diagnose::MaterialTable::read(app::data_directory().string());
  for (const auto &g : table.groups())
  {
    ASSERT_TRUE(g.simulated_cohesion.has_value()) << g.group;
    const double phi = *g.simulated_friction_angle * 3.14159265358979323846 / 180;
    const double ucs = 2 * *g.simulated_cohesion * std::cos(phi) / (1 - std::sin(phi));
    EXPECT_NEAR(ucs / g.ucs, 1.0, 0.005) << g.group;
    EXPECT_LT(*g.simulated_friction_angle, *g.calibrated_friction_angle - 1.5) << g.group;
  }
}

TEST(MaterialTable, SimulatorCalibratedHoekBrownRocksCoverEveryGroup)
{
  // every group has a Hoek-Brown rock through UCS and BTS in the simulator: the groups with
  // triaxial data (M8-M10) a tension cut-off on their fitted envelope, the others an m_b on
  // a = 1/2. The 3-D disc's faces carry more tension than the plane closed form's centre, so the
  // simulator needs a stronger envelope in tension than the closed form's m_b (UCS^2 - 16 BTS^2)
  // / (UCS BTS): the disc-calibrated m_b lies below it, by 2-8 % for basalt's UCS/BTS of 17-21
  const auto table = diagnose::MaterialTable::read(app::data_directory().string());
  for (const auto &g : table.groups())
  {
    const bool triaxial = g.measured_cohesion.has_value();
    EXPECT_EQ(g.simulated_cutoff.has_value(), triaxial) << g.group;
    EXPECT_EQ(g.simulated_mb.has_value(), !triaxial) << g.group;
    if (triaxial)
      continue;
    const double closed = (g.ucs * g.ucs - 16 * g.bts * g.bts) / (g.ucs * g.bts);
    EXPECT_LT(*g.simulated_mb, 0.98 * closed) << g.group;
    EXPECT_GT(*g.simulated_mb, 0.90 * closed) << g.group;
  }
}

TEST(Calibrate, Table6BtsOfM1DoesNotGiveTable4)
{
  const auto s = diagnose::calibrate_mohr_coulomb(282.18, 15.60);
  EXPECT_EQ(two_decimals(s.cohesion), "33.17");
  EXPECT_EQ(two_decimals(s.friction_angle), "63.54");
}

TEST(Calibrate, RoundTripThroughEqs14And15)
{
  // the inverse is closed-form: only round-off may remain
  const auto s = diagnose::calibrate_mohr_coulomb(231.0, 10.49);
  EXPECT_NEAR(diagnose::mohr_coulomb_ucs(s), 231.0, 1e-12 * 231.0);
  EXPECT_NEAR(diagnose::mohr_coulomb_bts(s), 10.49, 1e-12 * 231.0);
}

TEST(Calibrate, MeasuredM8GivesThePapersPrediction)
{
  // Section 3.2: c = 49.17 MPa, phi = 49.78 deg predict UCS 268.58 and BTS 36.01 MPa
  const diagnose::MohrCoulombStrength m8{49.17, 49.78};
  EXPECT_EQ(two_decimals(diagnose::mohr_coulomb_ucs(m8)), "268.58");
  EXPECT_EQ(two_decimals(diagnose::mohr_coulomb_bts(m8)), "36.01");
}

TEST(Calibrate, RefusesBtsNotBelowUcs)
{
  EXPECT_THROW(diagnose::calibrate_mohr_coulomb(10, 10), std::invalid_argument);
  EXPECT_THROW(diagnose::calibrate_mohr_coulomb(10, 0), std::invalid_argument);
}

TEST(Calibrate, BrazilianStatePutsTheDiscCentreOnTheEnvelope)
{
  // the centre of a Brazilian disc (plane elasticity): compression 3 BTS along the load, tension
  // BTS across. With the --brazilian c, phi that state and uniaxial compression at the UCS lie
  // on the envelope sigma_1 = UCS + N sigma_3 (compression +), to round-off
  const double ucs = 282.18, bts = 15.43;
  const auto s     = diagnose::calibrate_mohr_coulomb_brazilian(ucs, bts);
  EXPECT_NEAR(diagnose::mohr_coulomb_ucs(s), ucs, 1e-12 * ucs);
  const double sin_phi = std::sin(s.friction_angle * M_PI / 180);
  const double n       = (1 + sin_phi) / (1 - sin_phi);
  EXPECT_NEAR(3 * bts, ucs + n * (-bts), 1e-10 * ucs);
  // with Eqs. 14-15 the same state is past the envelope: a disc splits below the BTS, at
  // UCS BTS / (UCS + 3 BTS) = 13.26 MPa for M1 (the coupled runs converge to 13.5 at 1-1.25 mm)
  const auto t          = diagnose::calibrate_mohr_coulomb(ucs, bts);
  const double sin_t    = std::sin(t.friction_angle * M_PI / 180);
  const double n_t      = (1 + sin_t) / (1 - sin_t);
  EXPECT_NEAR(diagnose::mohr_coulomb_ucs(t) / (3 + n_t), ucs * bts / (ucs + 3 * bts), 1e-10 * ucs);
  EXPECT_EQ(two_decimals(ucs * bts / (ucs + 3 * bts)), "13.26");
  // M1: c 36.08 MPa, phi 61.31 deg (cosim calibrate --brazilian)
  EXPECT_EQ(two_decimals(s.cohesion), "36.08");
  EXPECT_EQ(two_decimals(s.friction_angle), "61.31");
  EXPECT_THROW(diagnose::calibrate_mohr_coulomb_brazilian(40, 10), std::invalid_argument);
}

TEST(Calibrate, HoekBrownEnvelopeRecoversAKnownEnvelope)
{
  // strengths drawn from a known generalised Hoek-Brown envelope with a cut-off below its disc
  // strength: the fit returns it (the search's tolerances: 1e-12 in log m_b, 1e-10 in a; 1e-6
  // leaves room for the flat misfit near its minimum)
  diagnose::HoekBrownStrength truth;
  truth.sigma_ci = 200, truth.m_b = 12, truth.a = 0.7;
  const double bts = 0.9 * diagnose::hoek_brown_disc_strength(truth);
  truth.tensile    = bts;
  std::vector<diagnose::TriaxialStrength> t;
  for (const double s3 : {5.0, 20.0, 40.0, 60.0})
    t.push_back({s3, diagnose::hoek_brown_sigma1(truth, s3)});
  const auto h = diagnose::calibrate_hoek_brown(200, bts, t);
  EXPECT_NEAR(h.m_b, 12, 1e-6 * 12);
  EXPECT_NEAR(h.a, 0.7, 1e-6);
  EXPECT_DOUBLE_EQ(h.tensile, bts);
  EXPECT_NEAR(diagnose::hoek_brown_disc_strength(h), bts, 1e-12 * bts);
  // without triaxial strengths: a = 1/2 and the disc centre's state at failure (3 BTS, -BTS)
  // lies on the envelope, to round-off of the bisection
  const auto u = diagnose::calibrate_hoek_brown(282.18, 15.43, {});
  EXPECT_EQ(u.a, 0.5);
  EXPECT_NEAR(diagnose::hoek_brown_sigma1(u, -15.43), 3 * 15.43, 1e-9 * 282.18);
  EXPECT_NEAR(diagnose::hoek_brown_disc_strength(u), 15.43, 1e-9 * 15.43);
  EXPECT_THROW(diagnose::calibrate_hoek_brown(40, 10, {}), std::invalid_argument);
  EXPECT_THROW(diagnose::calibrate_hoek_brown(200, 10, {{10, 5}}), std::invalid_argument);
}

TEST(Calibrate, HoekBrownEnvelopeThroughTable3)
{
  // M8-M10: one curved envelope through UCS (exactly), BTS (the disc) and the measured
  // triaxial envelope at 10, 30 and 50 MPa: every miss under 1 % (measured: at most 0.92 %,
  // M10 at 30 MPa; a straight line fitted to UCS and BTS misses them by 1.3-2.7x)
  const auto table = diagnose::MaterialTable::read(app::data_directory().string());
  for (const char *name : {"M8", "M9", "M10"})
  {
    const auto &g = table.find(name);
    const auto t  = diagnose::triaxial_strengths(g);
    ASSERT_EQ(t.size(), 3u);
    const auto h = diagnose::calibrate_hoek_brown(g.ucs, g.bts, t);
    EXPECT_EQ(h.sigma_ci, g.ucs);
    EXPECT_NEAR(diagnose::hoek_brown_disc_strength(h), g.bts, 1e-9 * g.bts) << name;
    for (const auto &x : t)
      EXPECT_NEAR(diagnose::hoek_brown_sigma1(h, x.sigma3) / x.sigma1, 1.0, 0.01) << name << " " << x.sigma3;
    EXPECT_GT(h.a, 0.7) << name; // the measured envelope is a straight line: a far from 1/2
  }
}
