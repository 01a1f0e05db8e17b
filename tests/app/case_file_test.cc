// The case-file reader: the shipped cases read, the group lookup, explicit overrides.
#include <app/case_file.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <cmath>

namespace
{
  std::string source(const std::string &relative) { return std::string(COSIM_SOURCE_DIR) + "/" + relative; }
  // values go through text (%.10g) once: a relative 1e-12 is far below their printed digits
  void expect_close(double actual, double expected)
  {
    EXPECT_NEAR(actual, expected, 1e-12 * std::abs(expected));
  }
} // namespace

TEST(CaseFile, UcsCaseReadsTheGroupFromTables3And4)
{
  const auto c = app::read_case_file(source("cases/ucs/ucs.prm"), {});
  const auto &p = c.parameters;
  EXPECT_EQ(p.test, "UCS");
  EXPECT_EQ(p.name, "ucs");
  expect_close(p.diameter, 0.05);
  expect_close(p.length, 0.1);
  EXPECT_EQ(p.rock.group, "M1");
  expect_close(p.rock.youngs_modulus, 97.07e9); // Table 3
  expect_close(p.rock.poissons_ratio, 0.28);
  expect_close(p.rock.cohesion, 32.99e6); // Table 4
  expect_close(p.rock.friction_angle, 63.68);
  expect_close(p.rock.ucs, 282.18e6);
  expect_close(p.rock.density, 2900);
  expect_close(p.sph.spacing, 2.5e-3);
  EXPECT_EQ(p.sph.form, 8);
  expect_close(p.sph.cslh, 1.2);
  expect_close(p.sph.tssfac, 0.9);
  EXPECT_EQ(p.platens.model, "rigid");
  EXPECT_TRUE(c.warnings.empty());
  EXPECT_NE(c.used_parameters.find("set Group"), std::string::npos);
  EXPECT_NE(c.used_parameters.find("subsection SPH"), std::string::npos);
}

TEST(CaseFile, BtsAndCtcsCasesRead)
{
  const auto b = app::read_case_file(source("cases/bts/bts.prm"), {}).parameters;
  EXPECT_EQ(b.test, "BTS");
  expect_close(b.length, 0.025);
  const auto t = app::read_case_file(source("cases/ctcs/ctcs.prm"), {}).parameters;
  EXPECT_EQ(t.test, "CTCS");
  EXPECT_EQ(t.rock.group, "M8");
  expect_close(t.confining_pressure, 10e6);
  expect_close(t.rock.cohesion, 28.83e6);
}

TEST(CaseFile, MeasuredStrengthUsesTable3)
{
  const auto p = app::read_case_file(source("cases/ctcs/ctcs.prm"),
                                          {"Rock/Strength parameters=measured", "Rock/Group=M9"})
                   .parameters;
  expect_close(p.rock.cohesion, 45.27e6);
  expect_close(p.rock.friction_angle, 49.18);
  expect_close(p.rock.youngs_modulus, 80.65e9);
}

TEST(CaseFile, ExplicitKeysOverrideTheGroupAndLaterSetWins)
{
  const auto c = app::read_case_file(source("cases/ucs/ucs.prm"),
                                          {"Rock/Youngs modulus=50e9", "Rock/Group=M4", "SPH/FORM=1", "SPH/FORM=7"});
  expect_close(c.parameters.rock.youngs_modulus, 50e9);
  expect_close(c.parameters.rock.poissons_ratio, 0.25); // M4
  expect_close(c.parameters.rock.cohesion, 21.92e6);
  EXPECT_EQ(c.parameters.sph.form, 7);
  // used_parameters.prm holds the resolved values, so that it re-runs the same case
  EXPECT_NE(c.used_parameters.find("5e+10"), std::string::npos) << c.used_parameters;
}

TEST(CaseFile, TensionCutoffDefaultsToTheGroupsBts)
{
  const auto p = app::read_case_file(source("cases/bts/bts.prm"), {"Rock/Model=mohr-coulomb-cutoff"}).parameters;
  expect_close(p.rock.tensile_strength, 15.43e6);
  const auto q = app::read_case_file(source("cases/bts/bts.prm"), {}).parameters;
  EXPECT_LT(std::abs(q.rock.tensile_strength), 1e-300);
}

TEST(CaseFile, TssfacAboveOneIsAcceptedWithAWarning)
{
  // TSSFAC 5 is the injected instability the run itself must catch
  const auto c = app::read_case_file(source("cases/ucs/ucs.prm"), {"SPH/TSSFAC=5"});
  ASSERT_EQ(c.warnings.size(), 1u);
  EXPECT_NE(c.warnings[0].find("TSSFAC"), std::string::npos);
}

TEST(CaseFile, ErrorsAreInputErrors)
{
  EXPECT_THROW(app::read_case_file(source("cases/ucs/ucs.prm"), {"SPH/FORM=2"}), coupling::InputError);
  EXPECT_THROW(app::read_case_file("/nonexistent.prm", {}), coupling::InputError);
}
