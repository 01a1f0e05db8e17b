// Reliability: instability detection, checkpoint / restart and determinism of the coupled run.
// Every comparison of histories here is bitwise (memcmp of the doubles), on purpose: the contract
// is "identical", not "close", for the same thread count.
#include "history_compare.h"
#include "subprocess.h"
#include "test_seed.h"

#include <app/case_file.h>
#include <app/checkpoint.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <thread>
#include <unistd.h>

using namespace cosim_test;

namespace
{
  const std::string ucs_case = source("cases/ucs/ucs.prm");

  /// The small case of these tests: the default UCS at a 5 mm spacing (about 1,600 particles, a
  /// few hundred steps) up to 0.2 % strain (past the first yield at the platens), two SPH threads
  /// so that the threaded sums are exercised.
  const std::vector<std::string> small = {"SPH/Particle spacing=0.005", "SPH/Threads=2",
                                          "Loading/End strain=0.002", "Output/History rows=100",
                                          "Output/Progress=false"};

  coupling::CaseParameters small_case(std::vector<std::string> extra = {})
  {
    std::vector<std::string> o = small;
    o.insert(o.end(), extra.begin(), extra.end());
    return app::read_case_file(ucs_case, o).parameters;
  }

  /// Keeps what the run reports, in memory, and where a failed run's last good state was.
  struct RunRecorder : cosim_test::Recorder
  {
    long good_step             = -1;
    std::size_t good_particles = 0;
    std::size_t good_modes     = 0; ///< particles whose failure mode the state holds
    void last_good_state(std::size_t step, double, const coupling::ParticleSnapshot &p) override
    {
      good_step      = static_cast<long>(step);
      good_particles = p.n;
      good_modes     = p.failure_mode.size();
    }
  };

  /// The reference run, once per test program.
  struct Reference
  {
    std::vector<coupling::HistoryRow> rows;
    std::size_t n_steps = 0;
  };
  const Reference &reference_run()
  {
    static const Reference ref = [] {
      RunRecorder r;
      Reference out;
      out.n_steps = coupling::run_case(small_case(), r).n_steps;
      out.rows    = r.rows;
      return out;
    }();
    return ref;
  }
  const std::vector<coupling::HistoryRow> &uninterrupted()
  {
    return reference_run().rows;
  }
} // namespace

TEST(Determinism, TwoRunsGiveIdenticalHistories)
{
  RunRecorder second;
  const coupling::Summary s = coupling::run_case(small_case(), second);
  ASSERT_GT(s.n_steps, 100u) << "the case must run long enough to test anything";
  ASSERT_GT(second.rows.size(), 20u);
  EXPECT_TRUE(identical(uninterrupted(), second.rows));
}

TEST(Restart, StoppedAtARandomStepAndRestartedFromTheFileGivesTheSameHistory)
{
  const auto reference = uninterrupted();
  // a random step inside the run: a fixed seed (COSIM_TEST_SEED draws another; it is printed)
  const unsigned seed = coupling::test::test_seed(20261123u);
  SCOPED_TRACE("seed " + std::to_string(seed));
  const std::size_t n_steps = reference_run().n_steps;
  std::mt19937 random(seed);
  const long stop_at = std::uniform_int_distribution<long>(5, long(n_steps) - 5)(random);
  SCOPED_TRACE("stopped after step " + std::to_string(stop_at) + " of " + std::to_string(n_steps));

  RunRecorder first;
  EXPECT_THROW(
    coupling::run_case(small_case({"Output/Stop after steps=" + std::to_string(stop_at)}), first),
    coupling::RunInterrupted);
  ASSERT_EQ(first.n_checkpoints, 1u);
  EXPECT_EQ(first.checkpoint_step, std::size_t(stop_at));
  EXPECT_LT(first.rows.size(), reference.size());

  // through the HDF5 file, as cosim run --restart does
  Sandbox box;
  const std::string file = (box.dir() / "checkpoint.h5").string();
  app::write_checkpoint(file, first.last_checkpoint);
  const coupling::StateArrays state = app::read_checkpoint(file);
  ASSERT_EQ(state.size(), first.last_checkpoint.size());
  for (const auto &[name, values] : first.last_checkpoint)
  {
    ASSERT_EQ(state.at(name).size(), values.size()) << name;
    EXPECT_EQ(std::memcmp(state.at(name).data(), values.data(), values.size() * sizeof(double)), 0)
      << name;
  }
  RunRecorder second;
  coupling::run_case(small_case({"Output/Stop after steps=" + std::to_string(stop_at)}), second,
                     &state);
  EXPECT_TRUE(identical(reference, second.rows));
}

// The same with elastic (FEM) platens and friction: the platen state (u, v, K u, ...) and the
// contact stick springs must come back too.
TEST(Restart, ElasticPlatensWithFrictionContinueBitwise)
{
  const std::vector<std::string> extra = {"Platens/Model=elastic",
                                          "Platens/Friction coefficient=0.3"};
  RunRecorder whole;
  const std::size_t n_steps = coupling::run_case(small_case(extra), whole).n_steps;
  ASSERT_GT(n_steps, 60u);
  const unsigned seed = coupling::test::test_seed(20261124u);
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937 random(seed);
  const long stop_at = std::uniform_int_distribution<long>(40, long(n_steps) - 5)(random);
  SCOPED_TRACE("stopped after step " + std::to_string(stop_at) + " of " + std::to_string(n_steps));
  auto with_stop = extra;
  with_stop.push_back("Output/Stop after steps=" + std::to_string(stop_at));
  RunRecorder first;
  EXPECT_THROW(coupling::run_case(small_case(with_stop), first), coupling::RunInterrupted);
  // the state holds what this test is about: a deformed platen and loaded stick springs
  auto max_abs = [&](const std::string &name) {
    return cosim_test::max_abs(first.last_checkpoint, name);
  };
  EXPECT_GT(max_abs("platen_top.u"), 0.0);
  EXPECT_GT(max_abs("contact_top.tangential_force") + max_abs("contact_bottom.tangential_force"),
            0.0);
  RunRecorder second;
  coupling::run_case(small_case(with_stop), second, &first.last_checkpoint);
  EXPECT_TRUE(identical(whole.rows, second.rows));
}

// Body-fitted particles (rings): the checkpoint holds them, the restart rebuilds the same set
// from the case, and the run continues bitwise; a lattice checkpoint does not fit the rings.
TEST(Restart, BodyFittedParticlesContinueBitwise)
{
  // the first 120 steps (13 history rows), whole and stopped at
  // step 60 then continued
  auto fitted_until = [](const long step) {
    // one thread: a small run waits less (the threaded sums are the other tests')
    return small_case({"SPH/Particle arrangement=body-fitted", "SPH/Threads=1",
                       "Output/Stop after steps=" + std::to_string(step)});
  };
  RunRecorder whole;
  EXPECT_THROW(coupling::run_case(fitted_until(120), whole), coupling::RunInterrupted);
  ASSERT_GT(whole.rows.size(), 10u);
  RunRecorder first;
  EXPECT_THROW(coupling::run_case(fitted_until(60), first), coupling::RunInterrupted);
  RunRecorder second;
  EXPECT_THROW(coupling::run_case(fitted_until(120), second, &first.last_checkpoint),
               coupling::RunInterrupted);
  EXPECT_TRUE(identical(whole.rows, second.rows));
  // the lattice's checkpoint does not fit the rings (another particle count)
  RunRecorder lattice;
  EXPECT_THROW(coupling::run_case(small_case({"Output/Stop after steps=10"}), lattice),
               coupling::RunInterrupted);
  RunRecorder refused;
  EXPECT_THROW(coupling::run_case(fitted_until(120), refused, &lattice.last_checkpoint),
               coupling::InputError);
}

TEST(Restart, PeriodicCheckpointsDoNotChangeTheRun)
{
  RunRecorder r;
  coupling::run_case(small_case({"Output/Checkpoint interval=50"}), r);
  EXPECT_GE(r.n_checkpoints, 2u);
  EXPECT_EQ(r.checkpoint_step % 50, 0u);
  EXPECT_TRUE(identical(uninterrupted(), r.rows));
}

TEST(Restart, TimedCheckpointsAreWrittenWhenTheirIntervalHasPassed)
{
  // an interval far below one step's wall time: a checkpoint after every step, the last one the
  // stop's
  RunRecorder r;
  EXPECT_THROW(coupling::run_case(
                 small_case({"Output/Checkpoint minutes=1e-9", "Output/Stop after steps=12"}), r),
               coupling::RunInterrupted);
  EXPECT_EQ(r.n_checkpoints, 12u);
  EXPECT_EQ(r.checkpoint_step, 12u);
}

TEST(Restart, CheckpointOfAnotherCaseIsRefused)
{
  RunRecorder first;
  EXPECT_THROW(coupling::run_case(small_case({"Output/Stop after steps=10"}), first),
               coupling::RunInterrupted);
  RunRecorder second;
  try
  {
    coupling::run_case(small_case({"SPH/Particle spacing=0.0045"}), second, &first.last_checkpoint);
    FAIL() << "a checkpoint of a 5 mm lattice was accepted by a 4.5 mm case";
  }
  catch (const coupling::InputError &e)
  {
    EXPECT_NE(std::string(e.what()).find("checkpoint"), std::string::npos) << e.what();
  }
}

// TSSFAC 5: five times the stable step. The run must stop within one step of the first bad
// state, say what and where, and hand over the state of the step before.
TEST(Instability, TssfacFiveIsCaughtWithinOneStepWithItsLastGoodState)
{
  RunRecorder r;
  try
  {
    coupling::run_case(small_case({"SPH/TSSFAC=5"}), r);
    FAIL() << "TSSFAC 5 ran to the end";
  }
  catch (const coupling::InstabilityError &e)
  {
    const std::string what = e.what();
    ASSERT_GE(r.good_step, 0) << "no last good state reported";
    EXPECT_GT(r.good_particles, 1000u);
    // detected at the step right after the last good one
    EXPECT_EQ(what.rfind("step " + std::to_string(r.good_step + 1) + ",", 0), 0u) << what;
    for (const char *part : {"particle ", ") m", "likely cause", "TSSFAC", "last good state: step"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " missing in: " << what;
  }
}

namespace
{
  /// Runs a cutter case (indentation or linear cutting, small: 3 mm spacing, a 30 mm block) at
  /// TSSFAC 5 and checks what TssfacFiveIsCaught... checks for UCS: the run loop catches it within
  /// one step of its last good state, reports that state and says what, where and why.
  void expect_caught_with_last_good_state(const std::string &file,
                                          const std::vector<std::string> &case_options)
  {
    std::vector<std::string> o = {"SPH/TSSFAC=5",          "SPH/Particle spacing=0.003",
                                  "SPH/Threads=2",         "Output/History rows=60",
                                  "Output/Snapshots=3",    "Output/Progress=false",
                                  "Cutter/Block width=0.03", "Cutter/Block height=0.03"};
    o.insert(o.end(), case_options.begin(), case_options.end());
    const coupling::CaseParameters p = app::read_case_file(file, o).parameters;
    RunRecorder r;
    try
    {
      coupling::run_case(p, r);
      FAIL() << p.test << " at TSSFAC 5 ran to the end";
    }
    catch (const coupling::InstabilityError &e)
    {
      const std::string what = e.what();
      ASSERT_GE(r.good_step, 0) << "no last good state reported";
      // every particle of the 30 mm block, whose outer layers are held
      EXPECT_GT(r.good_particles, 500u);
      EXPECT_EQ(r.good_modes, r.good_particles) << "the last good state has every failure mode";
      EXPECT_EQ(what.rfind("step " + std::to_string(r.good_step + 1) + ",", 0), 0u) << what;
      for (const char *part : {"likely cause", "TSSFAC", "Cutter/Speed", "last good state: step"})
        EXPECT_NE(what.find(part), std::string::npos) << part << " missing in: " << what;
    }
  }
} // namespace

// The cutter drivers share the laboratory tests' run loop: the full stability check (positions,
// stress, energy, time step, the cutter) and the last good state, not only a finite-position
// check every few steps.
TEST(Instability, IndentationAtTssfacFiveIsCaughtWithItsLastGoodState)
{
  expect_caught_with_last_good_state(source("cases/indentation/indentation.prm"),
                                     {"Cutter/Shape=cone", "Cutter/Tip radius=0",
                                      "Cutter/Penetration=0.006", "Cutter/Speed=4",
                                      "Cutter/Block length=0.03"});
}

TEST(Instability, LinearCuttingAtTssfacFiveIsCaughtWithItsLastGoodState)
{
  expect_caught_with_last_good_state(source("cases/linear-cutting/linear-cutting.prm"),
                                     {"Cutter/Disc diameter=0.06", "Cutter/Tip width=0.006",
                                      "Cutter/Penetration=0.006", "Cutter/Cut length=0.034",
                                      "Cutter/Block length=0.06"});
}

TEST(Instability, CosimExitsWithThreeAndWritesTheLastGoodState)
{
  Sandbox box;
  std::vector<std::string> args = {"run", ucs_case, "--quiet",     "-o",
                                   "out", "--set",  "SPH/TSSFAC=5"};
  for (const auto &s : small)
  {
    args.push_back("--set");
    args.push_back(s);
  }
  const Result r = run_cosim(box, args);
  EXPECT_EQ(r.status, 3) << r.err;
  EXPECT_NE(r.err.find("unstable run: step "), std::string::npos) << r.err;
  const fs::path failed = box.dir() / "out.failed";
  EXPECT_FALSE(fs::exists(box.dir() / "out")) << "an unstable run is not a result";
  for (const char *f :
       {"last_good_state.h5", "last_good_state.xdmf", "failure.txt", "summary.json", "history.csv"})
    EXPECT_TRUE(fs::exists(failed / f)) << f;
  const std::string summary = read_file(failed / "summary.json");
  EXPECT_NE(summary.find("\"status\": \"unstable\""), std::string::npos) << summary;
  EXPECT_NE(summary.find("\"last_good_state\": {\"file\": \"last_good_state.h5\""),
            std::string::npos)
    << summary;
}

// The real thing: SIGTERM to a running cosim, then cosim run --restart; history.csv must equal
// the one of an uninterrupted run byte for byte.
TEST(Restart, SigtermThenRestartGivesTheUninterruptedHistoryCsv)
{
  Sandbox box;
  std::vector<std::string> args = {"run", ucs_case, "--quiet"};
  for (const auto &s : small)
  {
    args.push_back("--set");
    args.push_back(s);
  }
  std::vector<std::string> full = args;
  full.insert(full.end(), {"-o", "full"});
  ASSERT_EQ(run_cosim(box, full).status, 0);

  // the interrupted run checkpoints every 20 steps; its first checkpoint shows that the time loop
  // is running, and SIGTERM goes in then
  std::vector<std::string> cut = args;
  cut.insert(cut.end(), {"-o", "cut", "--set", "Output/Checkpoint interval=20"});
  const Interrupted stopped = sigterm_at_first_checkpoint(box, cut, 30.0);
  EXPECT_TRUE(stopped.checkpoint_seen) << "no periodic checkpoint within 30 s";
  ASSERT_EQ(stopped.status, 4) << "SIGTERM must end the run cleanly with status 4";
  const fs::path cut_dir = box.dir() / "cut";
  for (const char *f : {"checkpoint.h5", "used_parameters.prm", "history.csv", "summary.json"})
    EXPECT_TRUE(fs::exists(cut_dir / f)) << f;
  EXPECT_NE(read_file(cut_dir / "summary.json").find("\"status\": \"interrupted\""),
            std::string::npos);
  const std::string partial   = read_file(cut_dir / "history.csv");
  const std::string reference = read_file(box.dir() / "full" / "history.csv");
  ASSERT_LT(partial.size(), reference.size()) << "the run ended before SIGTERM arrived";

  const Result restarted = run_cosim(box, {"run", "--restart", "cut", "--quiet"});
  ASSERT_EQ(restarted.status, 0) << restarted.err;
  EXPECT_TRUE(read_file(cut_dir / "history.csv") == reference) << "restarted history.csv differs";
  EXPECT_TRUE(fs::exists(cut_dir / "summary.json"));
  EXPECT_EQ(read_file(cut_dir / "summary.json").find("interrupted"), std::string::npos);
  // the snapshots: the interrupted run's up to its checkpoint, then the restarted run's; the same
  // times as the uninterrupted run's
  auto times = [](const std::string &xdmf) {
    std::vector<std::string> t;
    for (auto at = xdmf.find("<Time Value="); at != std::string::npos;
         at      = xdmf.find("<Time Value=", at + 1))
      t.push_back(xdmf.substr(at, xdmf.find('>', at) - at));
    return t;
  };
  const auto t_full = times(read_file(box.dir() / "full" / "results.xdmf"));
  EXPECT_GT(t_full.size(), 2u);
  EXPECT_EQ(times(read_file(cut_dir / "results.xdmf")), t_full);
}

TEST(Restart, BadRestartArgumentsAreInputErrors)
{
  Sandbox box;
  Result r = run_cosim(box, {"run", "--restart", "nowhere"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("used_parameters.prm"), std::string::npos) << r.err;
  r = run_cosim(box, {"run", ucs_case, "--restart", "nowhere"});
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find("takes no case file"), std::string::npos) << r.err;
  // a folder with parameters but a broken checkpoint
  box.write("dir/used_parameters.prm",
            read_file(ucs_case) +
              "subsection Rock\n  set Data directory = " + source("cases/data") + "\nend\n");
  box.write("dir/checkpoint.h5", "not HDF5");
  r = run_cosim(box, {"run", "--restart", "dir"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_NE(r.err.find("checkpoint"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
}

// More malformed inputs (tests/app/bad_input_test.cc has the first 41): every range the
// case file checks that has no test there, and the reliability keys. Each: exit status 2, one
// line naming the key and what is accepted, nothing written.
TEST(BadInput, EveryRangeCheckNamesItsKeyAndTheAcceptedRange)
{
  const std::vector<std::pair<std::string, std::vector<std::string>>> cases = {
    {"Test/Diameter=0", {"Test/Diameter", "(0, 10] m"}},
    {"Test/Length=-0.1", {"Test/Length", "(0, 10] m"}},
    {"Rock/Density=0", {"Rock/Density", "(0, 30000) kg/m^3"}},
    {"Rock/Youngs modulus=-1", {"Rock/Youngs modulus"}},
    {"Rock/Softening strain=1", {"Rock/Softening strain", "(0, 1)"}},
    {"Rock/Residual fraction=1.5", {"Rock/Residual fraction", "[0, 1]"}},
    {"Rock/Softening law=energy", {"Rock/Softening law", "fracture energy"}},
    {"Rock/Fracture energy=0", {"Rock/Fracture energy", "(0, 1e6) J/m^2"}},
    {"Rock/Shear fracture energy ratio=0.5", {"Rock/Shear fracture energy ratio", "[1, 1000]"}},
    {"SPH/CSLH=3", {"SPH/CSLH"}},
    {"SPH/Hourglass coefficient=2", {"SPH/Hourglass coefficient", "[0, 1]"}},
    {"SPH/Threads=-1", {"SPH/Threads", "[0, 4096]"}},
    {"Platens/Friction coefficient=-0.1", {"Platens/Friction coefficient", "[0, 2]"}},
    {"Platens/Contact stiffness scale=2", {"Platens/Contact stiffness scale"}},
    // a penalty setting on the kinematic (default) interface would be read and ignored
    {"Platens/Contact stiffness scale=0.4", {"Platens/Contact stiffness scale", "Contact method = penalty"}},
    {"Platens/Contact method=spring", {"Platens/Contact method", "automatic, penalty, kinematic"}},
    {"Platens/Contact tolerance=0", {"Platens/Contact tolerance", "(0, 0.01]"}},
    // rigid platens: the tolerance would be read and ignored
    {"Platens/Contact tolerance=1e-5", {"Platens/Contact tolerance", "elastic platens only"}},
    {"Platens/Contact patch points=17", {"Platens/Contact patch points", "[0, 16]"}},
    // rigid platens: the patch points and the loaded face would be read and ignored
    {"Platens/Contact patch points=2", {"Platens/Contact patch points", "elastic platens only"}},
    {"Platens/Loaded face=roller", {"Platens/Loaded face", "Model = elastic"}},
    {"Platens/Loaded face=free", {"Platens/Loaded face", "clamped, roller"}},
    {"Platens/Poissons ratio=0.5", {"Platens/Poissons ratio", "[0, 0.5)"}},
    {"Loading/End strain=0.9", {"Loading/End strain", "(0, 0.5]"}},
    {"Loading/Post-peak drop=1", {"Loading/Post-peak drop", "(0, 1)"}},
    {"Output/History rows=1", {"Output/History rows", "[2, 10000000]"}},
    {"Output/Checkpoint interval=-1", {"Output/Checkpoint interval", ">= 0"}},
    {"Output/Checkpoint minutes=-5", {"Output/Checkpoint minutes", "[0, 1e6]"}},
    {"Output/Stop after steps=-2", {"Output/Stop after steps", ">= 0"}},
  };
  ASSERT_GE(cases.size(), 18u);
  for (const auto &[set, expected] : cases)
  {
    SCOPED_TRACE(set);
    Sandbox box;
    const Result r = run_cosim(box, {"run", ucs_case, "--quiet", "--set", set});
    EXPECT_EQ(r.status, 2) << r.err;
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line only:\n" << r.err;
    for (const auto &e : expected)
      EXPECT_NE(r.err.find(e), std::string::npos) << "message lacks '" << e << "': " << r.err;
    EXPECT_TRUE(listing(box.dir()).empty()) << "bad input must write nothing";
  }
}

// A crack band too wide for its fracture energy would snap back: refused, naming the key and the
// energy that the spacing needs (M1: f_t = 15.4 MPa, E = 97 GPa, band 5 mm: 6.1 J/m^2).
TEST(BadInput, ACrackBandThatWouldSnapBackIsRefused)
{
  Sandbox box;
  const Result r =
    run_cosim(box, {"run", ucs_case, "--quiet", "--set", "Rock/Softening law=fracture energy",
                    "--set", "Rock/Fracture energy=1"});
  EXPECT_EQ(r.status, 2) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("Rock/Fracture energy"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("snap back"), std::string::npos) << r.err;
  EXPECT_TRUE(listing(box.dir()).empty()) << "bad input must write nothing";
}
