// `cosim study`: a tiny elastic UCS swept over two rock groups and over two end strains at a
// coarse spacing (5 mm, about a second a run), checked against Hooke's law and Table 3; its bad
// input (exit 2, one line, nothing written); the Mohr-Coulomb envelope the CTCS rows are compared
// with.
#include "subprocess.h"

#include <diagnose/calibrate.h>
#include <diagnose/csv.h>
#include <app/study.h>
#include <coupling/references.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace cosim_test;

namespace
{
  const std::string ucs_case = source("cases/ucs/ucs.prm");

  /// Fixed settings of the tiny case: elastic rock, 5 mm spacing, stop at 0.1 % strain.
  std::vector<std::string> tiny(std::vector<std::string> args)
  {
    for (const auto *s :
         {"Rock/Model=elastic", "SPH/Particle spacing=0.005", "Loading/End strain=0.001"})
      args.insert(args.end(), {"--set", s});
    args.push_back("--quiet");
    return args;
  }

  void expect_bad_input(const Sandbox &box, const std::vector<std::string> &args,
                        const std::string &expected)
  {
    const auto before = listing(box.dir());
    const Result r    = run_cosim(box, args);
    EXPECT_EQ(r.status, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line only:\n" << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos)
      << "message lacks '" << expected << "': " << r.err;
    EXPECT_EQ(listing(box.dir()), before) << "bad input must write nothing";
  }
} // namespace

TEST(Study, GroupsOfAnElasticUcsFollowHookeAndTable3)
{
  Sandbox box;
  const Result r = run_cosim(box, tiny({"study", ucs_case, "--groups", "M1,M4", "-o", "groups"}));
  ASSERT_EQ(r.status, 0) << r.err;
  const fs::path out = box.dir() / "groups";
  ASSERT_TRUE(fs::exists(out / "study.csv"));
  EXPECT_TRUE(fs::exists(out / "study.png")) << "python3-matplotlib is part of tools/setup";
  const auto table = diagnose::CsvTable::read((out / "study.csv").string());
  ASSERT_EQ(table.n_rows(), 2u);
  const double table3_e[] = {97.07, 79.64}, table3_ucs[] = {282.18, 200.18};
  for (std::size_t i = 0; i < 2; ++i)
  {
    EXPECT_EQ(table.text(i, "Rock/Group"), i == 0 ? "M1" : "M4");
    EXPECT_EQ(table.text(i, "status"), "ok");
    EXPECT_TRUE(fs::exists(out / table.text(i, "folder") / "summary.json"))
      << table.text(i, "folder");
    // the reference is Table 3's fitted UCS, printed as read
    EXPECT_NEAR(table.number(i, "reference_MPa"), table3_ucs[i], 1e-9);
    // the error column is the peak against it
    EXPECT_NEAR(table.number(i, "error_percent"),
                100 * (table.number(i, "peak_stress_MPa") / table3_ucs[i] - 1), 1e-3);
    // gauge modulus against the group's E: the coupled elastic UCS physics test holds it to 0.2 %
    // at 2.5 mm; 5 mm has 10 particles across, so allow 3 %
    EXPECT_NEAR(table.number(i, "youngs_modulus_GPa"), table3_e[i], 0.03 * table3_e[i]);
    // an elastic rock stops at the end strain: the largest stress is E times 0.1 % (the
    // kinematic interface adds no compliance; 1 % for the last step's overshoot) and not below
    // 75 % of it (a soft interface would lower it)
    const double hooke = table3_e[i] * 1e3 * 0.001; // [MPa]
    EXPECT_LT(table.number(i, "peak_stress_MPa"), 1.01 * hooke);
    EXPECT_GT(table.number(i, "peak_stress_MPa"), 0.75 * hooke);
    EXPECT_GT(table.number(i, "n_steps"), 0);
  }
  // no staging folder left, only the study
  std::size_t entries = 0;
  for ([[maybe_unused]] const auto &e : fs::directory_iterator(box.dir()))
    ++entries;
  EXPECT_EQ(entries, 1u);
  // a second study into the same folder is refused (and changes nothing) without --force
  const auto before  = listing(out);
  const Result again = run_cosim(box, tiny({"study", ucs_case, "--groups", "M1", "-o", "groups"}));
  EXPECT_EQ(again.status, 2) << again.err;
  EXPECT_NE(again.err.find("--force"), std::string::npos) << again.err;
  EXPECT_EQ(listing(out), before);
}

TEST(Study, KeyValuesSweepDoublesTheStressWithTheStrain)
{
  Sandbox box;
  const Result r = run_cosim(box, tiny({"study", ucs_case, "--key", "Loading/End strain",
                                        "--values", "0.0005,0.001", "-o", "s"}));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto table = diagnose::CsvTable::read((box.dir() / "s" / "study.csv").string());
  ASSERT_EQ(table.n_rows(), 2u);
  EXPECT_EQ(table.text(0, "Loading/End strain"), "0.0005");
  // linear elasticity: twice the end strain, twice the stress; the contact's own compliance is
  // linear too, so only the load-path discretisation (about 1 % of a step count) separates them
  const double ratio = table.number(1, "peak_stress_MPa") / table.number(0, "peak_stress_MPa");
  EXPECT_NEAR(ratio, 2.0, 0.05);
  // the same modulus both times (secant 40-60 % of the largest stress): 2 %
  EXPECT_NEAR(table.number(1, "youngs_modulus_GPa"), table.number(0, "youngs_modulus_GPa"),
              0.02 * table.number(0, "youngs_modulus_GPa"));
}

namespace
{
  /// study.csv's rows without the wall_seconds column (the only one that differs between runs of
  /// the same case).
  std::vector<std::string> rows_without_wall_time(const fs::path &csv)
  {
    const auto table = diagnose::CsvTable::read(csv.string());
    std::vector<std::string> rows;
    for (std::size_t i = 0; i < table.n_rows(); ++i)
    {
      std::string row;
      for (const auto &c : table.columns())
        if (c != "wall_seconds")
          row += table.text(i, c) + ",";
      rows.push_back(row);
    }
    return rows;
  }
} // namespace

TEST(Study, JobsSideBySideGiveTheSequentialTable)
{
  Sandbox box;
  const std::vector<std::string> sweep = {"study", ucs_case, "--key", "Loading/End strain", "--values",
                                          "0.0005,0.001"};
  auto with = [&](std::vector<std::string> more) {
    std::vector<std::string> args = sweep;
    args.insert(args.end(), more.begin(), more.end());
    return tiny(args);
  };
  ASSERT_EQ(run_cosim(box, with({"-o", "one"})).status, 0);
  const Result r = run_cosim(box, with({"-o", "two", "--jobs", "2"}));
  ASSERT_EQ(r.status, 0) << r.err;
  // each run is the same deterministic `cosim run`, in a child process: the same numbers to the
  // last printed digit, in the planned order
  EXPECT_EQ(rows_without_wall_time(box.dir() / "two" / "study.csv"),
            rows_without_wall_time(box.dir() / "one" / "study.csv"));
  for (const auto &entry : fs::directory_iterator(box.dir() / "two"))
    EXPECT_NE(entry.path().extension(), ".log") << "a finished run leaves no log: " << entry.path();
}

TEST(Study, PrintedCommandsRunElsewhereAndCollect)
{
  Sandbox box;
  const std::vector<std::string> sweep = tiny({"study", ucs_case, "--key", "Loading/End strain", "--values",
                                               "0.0005,0.001", "-o", "batch"});
  auto with = [&](const char *option) {
    std::vector<std::string> args = sweep;
    args.push_back(option);
    return args;
  };
  const Result printed = run_cosim(box, with("--print-commands"));
  ASSERT_EQ(printed.status, 0) << printed.err;
  EXPECT_FALSE(fs::exists(box.dir() / "batch")) << "--print-commands runs and writes nothing";
  std::vector<std::string> lines;
  std::istringstream in(printed.out);
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  ASSERT_EQ(lines.size(), 2u) << printed.out;
  EXPECT_NE(lines[0].find(" run "), std::string::npos) << lines[0];
  EXPECT_NE(lines[0].find("Loading/End strain=0.0005"), std::string::npos) << lines[0];

  // before any run there is no OUTDIR to collect from: bad input
  EXPECT_EQ(run_cosim(box, with("--collect")).status, 2) << "OUTDIR does not exist yet";
  // the first command only, as a batch system would run it
  ASSERT_EQ(std::system(("cd " + shell_quote(box.dir().string()) + " && " + lines[0] + " 2>/dev/null").c_str()), 0);
  Result collected = run_cosim(box, with("--collect"));
  EXPECT_EQ(collected.status, 4) << "one run still missing: " << collected.err;
  auto table = diagnose::CsvTable::read((box.dir() / "batch" / "study.csv").string());
  ASSERT_EQ(table.n_rows(), 2u);
  EXPECT_EQ(table.text(0, "status"), "ok");
  EXPECT_EQ(table.text(1, "status"), "not run");
  ASSERT_EQ(std::system(("cd " + shell_quote(box.dir().string()) + " && " + lines[1] + " 2>/dev/null").c_str()), 0);
  collected = run_cosim(box, with("--collect"));
  ASSERT_EQ(collected.status, 0) << collected.err;
  table = diagnose::CsvTable::read((box.dir() / "batch" / "study.csv").string());
  ASSERT_EQ(table.n_rows(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
  {
    EXPECT_EQ(table.text(i, "status"), "ok");
    // the row is the run's summary.json, printed to 6 digits
    const std::string summary = read_file(box.dir() / "batch" / table.text(i, "folder") / "summary.json");
    const auto at             = summary.find("\"peak_stress_MPa\": ");
    ASSERT_NE(at, std::string::npos);
    const double peak = std::stod(summary.substr(at + 19));
    EXPECT_NEAR(table.number(i, "peak_stress_MPa"), peak, 1e-5 * peak);
  }
  // run folders of the same names made with other parameters are not taken for this study's
  std::vector<std::string> other = with("--collect");
  other.insert(other.end(), {"--set", "SPH/CSLH=1.3"});
  const Result mismatch = run_cosim(box, other);
  EXPECT_EQ(mismatch.status, 2) << mismatch.err;
  EXPECT_NE(mismatch.err.find("is not the case this study plans"), std::string::npos) << mismatch.err;
}

TEST(Study, SlurmExampleRunsAsWrittenWithBash)
{
  // cases/studies/slurm/study.sbatch outside Slurm: the same script, its runs as plain processes
  Sandbox box;
  std::string command = "cd " + shell_quote(box.dir().string()) + " && COSIM=" + shell_quote(cosim_binary()) +
                        " JOBS=2 bash " + shell_quote(source("cases/studies/slurm/study.sbatch")) + " out";
  for (const auto &a : tiny({ucs_case, "--key", "Loading/End strain", "--values", "0.0005,0.001"}))
    command += " " + shell_quote(a);
  ASSERT_EQ(std::system((command + " 2>/dev/null").c_str()), 0) << command;
  const auto table = diagnose::CsvTable::read((box.dir() / "out" / "study.csv").string());
  ASSERT_EQ(table.n_rows(), 2u);
  for (std::size_t i = 0; i < 2; ++i)
    EXPECT_EQ(table.text(i, "status"), "ok");
  // twice the end strain, twice the stress (as KeyValuesSweepDoublesTheStressWithTheStrain)
  EXPECT_NEAR(table.number(1, "peak_stress_MPa") / table.number(0, "peak_stress_MPa"), 2.0, 0.05);
}

TEST(Study, BadInputWritesNothing)
{
  Sandbox box;
  expect_bad_input(box, {"study", ucs_case, "--key", "SPH/Nonsense", "--values", "1,2"},
                   "Nonsense");
  // the second value is out of range: caught before the first one runs
  expect_bad_input(box, {"study", ucs_case, "--key", "SPH/FORM", "--values", "8,5"}, "FORM");
  expect_bad_input(box, {"study", ucs_case, "--values", "1,2"}, "--values without a --key");
  expect_bad_input(box, {"study", ucs_case, "--key", "SPH/CSLH"}, "has no --values");
  expect_bad_input(box, {"study", ucs_case, "--key", "SPH/CSLH", "--values", "1.2,,1.3"},
                   "empty value");
  expect_bad_input(box, {"study", ucs_case}, "nothing to vary");
  expect_bad_input(box, {"study", ucs_case, "--groups", "M1,M99"}, "M99");
  expect_bad_input(box, {"study", "--groups", "M1"}, "no case file");
  expect_bad_input(box, {"study", ucs_case, "--groups", "M1", "--frobnicate"}, "--frobnicate");
  expect_bad_input(box, {"study", ucs_case, "--groups", "M1", "--jobs", "0"}, "--jobs");
  expect_bad_input(box, {"study", ucs_case, "--groups", "M1", "--jobs", "two"}, "--jobs");
  expect_bad_input(box, {"study", ucs_case, "--groups", "M1", "--jobs", "2", "--collect"}, "exclude");
  expect_bad_input(box, {"study", ucs_case, "--groups", "M1", "--collect", "-o", "nowhere"}, "not a folder");
}

TEST(Study, HelpNamesTheOptions)
{
  Sandbox box;
  const Result r = run_cosim(box, {"study", "--help"});
  EXPECT_EQ(r.status, 0);
  for (const auto *o :
       {"usage: cosim study", "--key", "--values", "--vary", "--groups", "--jobs", "--print-commands",
        "--collect", "study.csv", "study.png"})
    EXPECT_NE(r.out.find(o), std::string::npos) << o;
  EXPECT_NE(run_cosim(box, {"--help"}).out.find("study"), std::string::npos);
}

TEST(Study, MohrCoulombAxialStrengthIsTheEnvelope)
{
  // sigma3 = 0: Eq. 14 (calibrate.cc's own closed form); Table 4 M1 gives Table 3's UCS to the
  // rounding of c and phi (two decimals: 0.1 %)
  const double c = 32.99e6, phi = 63.68;
  EXPECT_NEAR(coupling::mohr_coulomb_axial_strength(c, phi, 0),
              diagnose::mohr_coulomb_ucs({c, phi}), 1.0);
  EXPECT_NEAR(coupling::mohr_coulomb_axial_strength(c, phi, 0), 282.18e6, 0.001 * 282.18e6);
  // slope of the envelope: (1 + sin phi)/(1 - sin phi), exact in sigma3 (linear)
  const double s = std::sin(49.78 * M_PI / 180);
  EXPECT_NEAR(coupling::mohr_coulomb_axial_strength(49.17e6, 49.78, 30e6) -
                coupling::mohr_coulomb_axial_strength(49.17e6, 49.78, 0),
              30e6 * (1 + s) / (1 - s), 1e-6);
}
