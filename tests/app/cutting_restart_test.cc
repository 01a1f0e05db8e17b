// Checkpoint / restart and the stop signals of the cutter drivers (Test/Type = indentation,
// linear-cutting), as tests/app/reliability_test.cc checks them for UCS / BTS / CTCS. Histories
// are compared bitwise on purpose: the contract is "identical", not "close", for the same thread
// count.
#include "history_compare.h"
#include "subprocess.h"

#include <app/case_file.h>
#include <app/checkpoint.h>
#include <coupling/run_case.h>

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <random>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

using namespace cosim_test;

namespace
{
  const std::string indentation_case = source("cases/indentation/indentation.prm");
  const std::string cutting_case     = source("cases/linear-cutting/linear-cutting.prm");

  /// A cone pressed 6 mm into a Mohr-Coulomb block 30 mm on a side at 3 mm spacing (1,000
  /// particles, 3,000 steps; particles fail under the tip), two threads so that the threaded
  /// sums are exercised. A sharp tip at TSSFAC 0.9, not the case's rounded tip at 0.45: half the
  /// steps, and a restart must continue any run bitwise, whatever its physics. The intact
  /// friction angle after failure (not the case's 35 deg): with the weaker crushed rock this
  /// sharp tip at 0.9 goes unstable at 5.98 mm (exit status 3); the crushed-rock friction is
  /// restarted by the linear-cutting test below.
  const std::vector<std::string> small_indentation = {
    "Cutter/Tip radius=0",      "SPH/TSSFAC=0.9",
    "Cutter/Shape=cone",        "SPH/Particle spacing=0.003",
    "Cutter/Penetration=0.006", "Cutter/Speed=4",
    "Cutter/Block length=0.03", "Cutter/Block width=0.03",
    "Cutter/Block height=0.03", "SPH/Threads=2",
    "Output/History rows=60",   "Output/Snapshots=3",
    "Output/Progress=false",    "Rock/Residual friction angle="};

  /// A 60 mm disc, 6 mm deep, across a 60 x 30 x 30 mm block at 3 mm spacing: rock fails and
  /// leaves the contact as chip within the first 3,600 steps, so the chip flags and the contact
  /// forces they read are part of the state. Only those steps are run (Output/Stop after
  /// steps), which is all a restart needs; one thread (the indentation test runs two).
  const std::vector<std::string> small_cut = {
    "SPH/Particle spacing=0.003", "Cutter/Disc diameter=0.06", "Cutter/Tip width=0.006",
    "Cutter/Penetration=0.006",   "Cutter/Cut length=0.034",   "Cutter/Block length=0.06",
    "Cutter/Block width=0.03",    "Cutter/Block height=0.03",  "SPH/Threads=1",
    "Output/History rows=300",    "Output/Snapshots=3",        "Output/Progress=false"};

  coupling::CaseParameters make(const std::string &file, std::vector<std::string> o,
                                const std::vector<std::string> &extra = {})
  {
    o.insert(o.end(), extra.begin(), extra.end());
    return app::read_case_file(file, o).parameters;
  }

  /// Runs `file` with `o` to step `end` (Output/Stop after steps), then stopped after a
  /// pseudo-random step in [lo, end - two history rows], through checkpoint.h5, and restarted to
  /// `end`: the histories must be identical. Returns the checkpoint.
  coupling::StateArrays stop_and_restart(const std::string &file, const std::vector<std::string> &o,
                                         const long lo, const long end)
  {
    const std::vector<std::string> to_end = {"Output/Stop after steps=" + std::to_string(end)};
    Recorder whole;
    EXPECT_THROW(coupling::run_case(make(file, o, to_end), whole), coupling::RunInterrupted);
    EXPECT_GT(whole.rows.size(), 10u) << "the case must run long enough to test anything";
    // a fixed seed (a failure must be reproducible) and a stop at least two history rows
    // before the end, so that the restarted run has rows of its own to compare (a stop after
    // the last row, as at step 1993 of 2000 with a row every 50 steps, tests nothing)
    const unsigned seed = 20261201u + static_cast<unsigned>(lo);
    SCOPED_TRACE("seed " + std::to_string(seed));
    std::mt19937 random(seed);
    const long row_steps = end / static_cast<long>(std::max<std::size_t>(1, whole.rows.size())) + 1;
    const long stop_at   = std::uniform_int_distribution<long>(lo, end - 2 * row_steps)(random);
    SCOPED_TRACE("stopped after step " + std::to_string(stop_at) + " of " + std::to_string(end));
    const std::vector<std::string> stop = {"Output/Stop after steps=" + std::to_string(stop_at)};
    Recorder first;
    EXPECT_THROW(coupling::run_case(make(file, o, stop), first), coupling::RunInterrupted);
    EXPECT_EQ(first.n_checkpoints, 1u);
    EXPECT_EQ(first.checkpoint_step, std::size_t(stop_at));
    EXPECT_LT(first.rows.size(), whole.rows.size());
    // through the HDF5 file, as cosim run --restart does
    Sandbox box;
    const std::string path = (box.dir() / "checkpoint.h5").string();
    app::write_checkpoint(path, first.last_checkpoint);
    const coupling::StateArrays state = app::read_checkpoint(path);
    Recorder second;
    EXPECT_THROW(coupling::run_case(make(file, o, to_end), second, &state),
                 coupling::RunInterrupted);
    EXPECT_TRUE(identical(whole.rows, second.rows));
    return state;
  }
} // namespace

TEST(CutterRestart, IndentationStoppedAtARandomStepContinuesBitwise)
{
  // from step 1,200 on the cone is in the rock (contact, failed particles, loaded springs)
  const coupling::StateArrays s = stop_and_restart(indentation_case, small_indentation, 1200, 2000);
  EXPECT_GT(max_abs(s, "driver.contact_force"), 0.0) << "stopped before the cone touched";
}

TEST(CutterRestart, LinearCuttingWithReleasedChipContinuesBitwise)
{
  const coupling::StateArrays s = stop_and_restart(cutting_case, small_cut, 2800, 3600);
  EXPECT_GT(max_abs(s, "driver.released"), 0.0) << "stopped before any chip was released";
}

TEST(CutterRestart, CheckpointOfALaboratoryCaseIsRefused)
{
  Recorder first;
  const std::vector<std::string> ucs = {"SPH/Particle spacing=0.005", "Output/Stop after steps=5",
                                        "Output/Progress=false"};
  EXPECT_THROW(coupling::run_case(make(source("cases/ucs/ucs.prm"), ucs), first),
               coupling::RunInterrupted);
  Recorder second;
  try
  {
    coupling::run_case(make(indentation_case, small_indentation), second, &first.last_checkpoint);
    FAIL() << "a UCS checkpoint was accepted by an indentation case";
  }
  catch (const coupling::InputError &e)
  {
    EXPECT_NE(std::string(e.what()).find("checkpoint"), std::string::npos) << e.what();
  }
}

// Through cosim: SIGTERM to a running indentation (exit status 4, checkpoint written), then
// cosim run --restart; history.csv must equal the uninterrupted run's byte for byte.
TEST(CutterRestart, SigtermThenRestartGivesTheUninterruptedHistoryCsv)
{
  Sandbox box;
  std::vector<std::string> args = {"run", indentation_case, "--quiet"};
  for (const auto &s : small_indentation)
    args.insert(args.end(), {"--set", s});
  std::vector<std::string> full = args;
  full.insert(full.end(), {"-o", "full"});
  ASSERT_EQ(run_cosim(box, full).status, 0);

  std::vector<std::string> cut = args;
  cut.insert(cut.end(), {"-o", "cut", "--set", "Output/Checkpoint interval=200"});
  // the first periodic checkpoint shows that the time loop runs: SIGTERM goes in then
  const Interrupted stopped = sigterm_at_first_checkpoint(box, cut, 15.0);
  EXPECT_TRUE(stopped.checkpoint_seen) << "no periodic checkpoint within 15 s";
  ASSERT_EQ(stopped.status, 4) << "SIGTERM must end the run cleanly with status 4";
  const fs::path cut_dir = box.dir() / "cut";
  EXPECT_TRUE(fs::exists(cut_dir / "checkpoint.h5"));
  EXPECT_NE(read_file(cut_dir / "summary.json").find("\"status\": \"interrupted\""),
            std::string::npos);
  const std::string reference = read_file(box.dir() / "full" / "history.csv");
  ASSERT_LT(read_file(cut_dir / "history.csv").size(), reference.size())
    << "the run ended before SIGTERM arrived";

  const Result restarted = run_cosim(box, {"run", "--restart", "cut", "--quiet"});
  ASSERT_EQ(restarted.status, 0) << restarted.err;
  EXPECT_TRUE(read_file(cut_dir / "history.csv") == reference) << "restarted history.csv differs";
  const std::string summary = read_file(cut_dir / "summary.json");
  EXPECT_EQ(summary.find("interrupted"), std::string::npos);
  EXPECT_NE(summary.find("cavity_expansion_force_kN"), std::string::npos);
}
