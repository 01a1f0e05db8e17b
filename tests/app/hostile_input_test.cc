// Hostile input and faults against the built `cosim`: result folders it must not replace, cases
// too large for the machine, damaged or foreign checkpoints, files with byte-order marks, NUL
// bytes, other encodings and huge lines, empty option values, signals. Every refusal is exit 2
// with one short line naming the culprit and nothing written; every fault a message and a clean
// exit, never a crash. Runs are the default UCS case at 5 mm spacing to 0.05 % strain (seconds).
#include "subprocess.h"

#include <app/checkpoint.h>
#include <coupling/errors.h>
#include <diagnose/csv.h>
#include <diagnose/text_input.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <sstream>

using namespace cosim_test;

namespace
{
  const std::string ucs_case = source("cases/ucs/ucs.prm");

  /// The small run of these tests.
  std::vector<std::string> quick(std::vector<std::string> args)
  {
    for (const char *a : {"--quiet", "--set", "SPH/Particle spacing=0.005", "--set", "Loading/End strain=0.0005",
                          "--set", "SPH/Threads=1"})
      args.push_back(a);
    return args;
  }

  /// Runs cosim in `dir` with `args`; `prefix` is shell text run before it (limits, traps).
  Result run_at(const fs::path &dir, const std::vector<std::string> &args, const std::string &prefix = "")
  {
    const fs::path capture = fs::path(dir.string() + ".capture");
    fs::create_directories(capture);
    std::string command = "cd " + shell_quote(dir.string()) + " && " + prefix + " exec " + shell_quote(cosim_binary());
    for (const auto &a : args)
      command += " " + shell_quote(a);
    command += " >" + shell_quote((capture / "out").string()) + " 2>" + shell_quote((capture / "err").string());
    const int raw = std::system(command.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : WIFSIGNALED(raw) ? 128 + WTERMSIG(raw) : -1;
    r.out    = read_file(capture / "out");
    r.err    = read_file(capture / "err");
    fs::remove_all(capture);
    return r;
  }

  /// One short valid-UTF-8 line on stderr.
  void expect_one_short_line(const Result &r)
  {
    ASSERT_FALSE(r.err.empty());
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << "one line only:\n" << r.err.substr(0, 2000);
    EXPECT_LE(r.err.size(), 1000u) << "a short line: " << r.err.substr(0, 2000);
    EXPECT_FALSE(diagnose::invalid_utf8_at(r.err).has_value()) << "stderr must be UTF-8";
  }

  /// Exit 2, one short line holding every fragment, nothing written in `dir`.
  void expect_refused(const fs::path &dir, const std::vector<std::string> &args,
                      const std::vector<std::string> &fragments, const std::string &prefix = "")
  {
    const auto before = listing(dir);
    const Result r    = run_at(dir, args, prefix);
    EXPECT_EQ(r.status, 2) << r.err.substr(0, 2000);
    expect_one_short_line(r);
    for (const auto &f : fragments)
      EXPECT_NE(r.err.find(f), std::string::npos) << "message lacks '" << f << "': " << r.err.substr(0, 2000);
    EXPECT_EQ(listing(dir), before) << "a refusal writes nothing";
  }

  void write_bytes(const fs::path &p, const std::string &bytes)
  {
    fs::create_directories(p.parent_path());
    std::ofstream(p, std::ios::binary) << bytes;
  }

  /// A copy of the shipped data tables in `dir`, table3's M1 row replaced by `m1_row` when given.
  std::string data_copy(const fs::path &dir, const std::string &m1_row = "", const std::string &prefix = "")
  {
    fs::create_directories(dir);
    for (const auto *f : {"table3_fitted_parameters.csv", "table4_calibrated.csv", "simulator_calibrated.csv"})
      fs::copy_file(source(std::string("cases/data/") + f), dir / f);
    std::string text = read_file(dir / "table3_fitted_parameters.csv");
    if (!m1_row.empty())
    {
      const auto at  = text.find("\nM1,") + 1;
      const auto end = text.find('\n', at);
      text.replace(at, end - at, m1_row);
    }
    write_bytes(dir / "table3_fitted_parameters.csv", prefix + text);
    return dir.string();
  }

  /// A small measured-data folder for `cosim diagnose`: material and strength of one group.
  fs::path diagnose_data(const fs::path &dir, const std::string &material_prefix = "")
  {
    write_bytes(dir / "material.csv", material_prefix + "group,E_GPa,nu,UCS_MPa,BTS_MPa\nM1,97.07,0.28,282.18,15.43\n");
    write_bytes(dir / "strength.csv", "test,group,sigma1_MPa,sigma3_MPa\nUCS,M1,282.18,0\nBTS,M1,0,-15.43\n");
    return dir;
  }

  /// A curve file with header `header` and forces `forces` [kN] at 0.01 mm steps.
  std::string curve(const std::vector<double> &forces, const std::string &test = "UCS")
  {
    std::ostringstream c;
    c << "# test: " << test << "\n# group: M1\n# diameter_mm: 50\n# length_mm: 100\n# displacement: platen\n"
      << "time_s,displacement_mm,force_kN\n";
    for (std::size_t i = 0; i < forces.size(); ++i)
      c << i << "," << 0.01 * i << "," << forces[i] << "\n";
    return c.str();
  }

  /// Starts cosim in `dir` (stdout, stderr to files beside it); returns its pid.
  pid_t spawn(const fs::path &dir, std::vector<std::string> args)
  {
    const std::string binary = cosim_binary();
    const pid_t pid          = fork();
    if (pid == 0)
    {
      if (chdir(dir.c_str()) != 0)
        _exit(127);
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, 1);
      const int err = open((dir / "spawn-err.txt").c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      dup2(err, 2);
      std::vector<char *> argv;
      argv.push_back(const_cast<char *>(binary.c_str()));
      for (auto &a : args)
        argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(binary.c_str(), argv.data());
      _exit(127);
    }
    return pid;
  }

  /// Waits up to `seconds` for `ready`; true when it came.
  template <typename Predicate>
  bool wait_for(Predicate ready, const double seconds)
  {
    const auto start = std::chrono::steady_clock::now();
    while (std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < seconds)
    {
      if (ready())
        return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    return ready();
  }

  /// Exit status of `pid` (128 + signal when killed).
  int reap(const pid_t pid)
  {
    int status = 0;
    waitpid(pid, &status, 0);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  }

  /// True when a hidden staging folder (".NAME.tmp-...") in `dir` holds a checkpoint.
  bool staging_checkpoint(const fs::path &dir)
  {
    std::error_code ec;
    for (const auto &e : fs::recursive_directory_iterator(dir, ec))
    {
      const std::string name = e.path().parent_path().filename().string();
      if (e.path().filename() == "checkpoint.h5" && name.rfind(".", 0) == 0 && name.find(".tmp") != std::string::npos)
        return true;
    }
    return false;
  }

  bool any_hidden_staging(const fs::path &dir)
  {
    for (const auto &p : listing(dir))
      if (p.find(".tmp-") != std::string::npos || p.find(".lock") != std::string::npos)
        return true;
    return false;
  }

  /// A long run with periodic checkpoints (stopped by the tests' signals long before its end).
  std::vector<std::string> long_run(const std::string &out)
  {
    return {"run", ucs_case, "-o", out, "--quiet", "--set", "SPH/Particle spacing=0.005", "--set",
            "Loading/End strain=0.02", "--set", "Output/Checkpoint interval=20", "--set", "SPH/Threads=1"};
  }

  /// An interrupted run (Output/Stop after steps, as on SIGTERM) into `out`; its checkpoint.
  fs::path interrupted_run(const fs::path &dir, const std::string &out, std::vector<std::string> extra = {})
  {
    std::vector<std::string> args = quick({"run", ucs_case, "-o", out, "--set", "Output/Stop after steps=30"});
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run_at(dir, args);
    EXPECT_EQ(r.status, 4) << r.err;
    return dir / out / "checkpoint.h5";
  }

  /// Flips one bit in the data (not the metadata) of the largest dataset of checkpoint `file`.
  void flip_particle_byte(const fs::path &file)
  {
    const coupling::StateArrays state = app::read_checkpoint(file.string());
    std::string bytes = read_file(file);
    // three non-zero neighbouring values of a particle array: a 24-byte pattern found once in
    // the file is the data itself, not metadata or free space
    for (const auto &[name, values] : state)
      for (std::size_t k = values.size() / 2; k + 1 < values.size() && k > 0; ++k)
      {
        if (values.size() < 64 || values[k - 1] == 0 || values[k] == 0 || values[k + 1] == 0)
          continue;
        const std::string pattern(reinterpret_cast<const char *>(values.data() + k - 1), 3 * sizeof(double));
        const auto at = bytes.find(pattern);
        if (at == std::string::npos || bytes.find(pattern, at + 1) != std::string::npos)
          continue;
        bytes[at + sizeof(double) + 2] ^= 0x10;
        write_bytes(file, bytes);
        return;
      }
    FAIL() << "no particle data found in " << file;
  }

  std::string replace_all(std::string text, const std::string &from, const std::string &to)
  {
    for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size()))
      text.replace(at, from.size(), to);
    return text;
  }
} // namespace

// ---------------------------------------------------------------- result folders

TEST(HostileFolders, OutputDotWithForceKeepsTheWorkingFolder)
{
  Sandbox box;
  const auto prm = box.write("c.prm", read_file(ucs_case));
  expect_refused(box.dir(), quick({"run", "c.prm", "-o", ".", "--force"}), {"working folder"});
  EXPECT_TRUE(fs::exists(prm));
}

TEST(HostileFolders, OutputDotSlashWithForceRefused)
{
  Sandbox box;
  box.write("c.prm", read_file(ucs_case));
  expect_refused(box.dir(), quick({"run", "c.prm", "-o", "./", "--force"}), {"working folder"});
}

TEST(HostileFolders, AbsoluteWorkingFolderWithForceRefused)
{
  Sandbox box;
  box.write("keep.txt", "mine\n");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", box.dir().string(), "--force"}), {"working folder"});
}

TEST(HostileFolders, ParentOfWorkingFolderWithForceRefused)
{
  Sandbox box;
  const fs::path inner = box.dir() / "a" / "b";
  fs::create_directories(inner);
  box.write("a/keep.txt", "mine\n");
  expect_refused(inner, quick({"run", ucs_case, "-o", "..", "--force"}), {"parents"});
  EXPECT_TRUE(fs::exists(box.dir() / "a" / "keep.txt"));
}

TEST(HostileFolders, HomeFolderWithForceRefused)
{
  Sandbox box;
  box.write("home/.profile", "x\n");
  fs::create_directories(box.dir() / "work");
  expect_refused(box.dir() / "work",
                 quick({"run", ucs_case, "-o", (box.dir() / "home").string(), "--force"}), {"home"},
                 "HOME=" + shell_quote((box.dir() / "home").string()));
  EXPECT_TRUE(fs::exists(box.dir() / "home" / ".profile"));
}

TEST(HostileFolders, FolderHoldingTheCaseFileRefused)
{
  Sandbox box;
  box.write("cases/c.prm", read_file(ucs_case));
  expect_refused(box.dir(), quick({"run", "cases/c.prm", "-o", "cases", "--force"}), {"holds the input"});
}

TEST(HostileFolders, ForceRefusesAFolderCosimDidNotWrite)
{
  Sandbox box;
  box.write("results/mine/notes.txt", "keep me\n");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "results/mine", "--force"}), {"not written by cosim"});
  EXPECT_EQ(read_file(box.dir() / "results/mine/notes.txt"), "keep me\n");
}

TEST(HostileFolders, DanglingSymlinkRefusedUpFront)
{
  Sandbox box;
  fs::create_symlink(box.dir() / "nowhere", box.dir() / "out");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out"}), {"symbolic link", "dangling"});
}

TEST(HostileFolders, SymlinkToAFolderRefused)
{
  Sandbox box;
  fs::create_directories(box.dir() / "real");
  fs::create_directory_symlink(box.dir() / "real", box.dir() / "out");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--force"}), {"symbolic link"});
}

TEST(HostileFolders, EmptyOutputOptionRefused)
{
  Sandbox box;
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", ""}), {"-o", "empty"});
}

TEST(HostileFolders, EmptyOutputEqualsOptionRefused)
{
  Sandbox box;
  expect_refused(box.dir(), quick({"run", ucs_case, "--output="}), {"--output", "empty"});
}

TEST(HostileFolders, SuccessfulRunLeavesItsMarker)
{
  Sandbox box;
  const Result r = run_at(box.dir(), quick({"run", ucs_case, "-o", "out"}));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(read_file(box.dir() / "out" / ".cosim-result").find("status: complete"), std::string::npos);
  EXPECT_FALSE(any_hidden_staging(box.dir())) << "no staging folder or lock left";
}

TEST(HostileFolders, ForceReplacesCosimsOwnResult)
{
  Sandbox box;
  ASSERT_EQ(run_at(box.dir(), quick({"run", ucs_case, "-o", "out"})).status, 0);
  box.write("out/stale.txt", "old\n");
  const Result r = run_at(box.dir(), quick({"run", ucs_case, "-o", "out", "--force"}));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_FALSE(fs::exists(box.dir() / "out" / "stale.txt"));
  EXPECT_TRUE(fs::exists(box.dir() / "out" / ".cosim-result"));
  EXPECT_FALSE(any_hidden_staging(box.dir()));
}

TEST(HostileFolders, InterruptedRunWithForceKeepsTheCompleteResult)
{
  Sandbox box;
  ASSERT_EQ(run_at(box.dir(), quick({"run", ucs_case, "-o", "out"})).status, 0);
  const std::string summary = read_file(box.dir() / "out" / "summary.json");
  const Result r = run_at(box.dir(), quick({"run", ucs_case, "-o", "out", "--force", "--set", "Output/Stop after steps=30"}));
  EXPECT_EQ(r.status, 4) << r.err;
  EXPECT_EQ(read_file(box.dir() / "out" / "summary.json"), summary) << "--force replaces only after success";
  EXPECT_TRUE(fs::exists(box.dir() / "out.interrupted" / "checkpoint.h5"));
  EXPECT_NE(r.err.find("out.interrupted"), std::string::npos) << r.err;
}

TEST(HostileFolders, InterruptedRunRestartsFromItsOwnFolder)
{
  Sandbox box;
  ASSERT_EQ(run_at(box.dir(), quick({"run", ucs_case, "-o", "out"})).status, 0);
  ASSERT_EQ(run_at(box.dir(), quick({"run", ucs_case, "-o", "out", "--force", "--set", "Output/Stop after steps=30"})).status, 4);
  const Result r = run_at(box.dir(), {"run", "--restart", "out.interrupted", "--quiet"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(read_file(box.dir() / "out.interrupted" / ".cosim-result").find("status: complete"), std::string::npos);
}

TEST(HostileFolders, SecondRunIntoAFolderBeingWrittenRefused)
{
  Sandbox box;
  const pid_t first = spawn(box.dir(), long_run("out"));
  ASSERT_TRUE(wait_for([&] { return staging_checkpoint(box.dir()); }, 120)) << "the first run never checkpointed";
  const Result second = run_at(box.dir(), quick({"run", ucs_case, "-o", "out"}));
  kill(first, SIGTERM);
  reap(first);
  EXPECT_EQ(second.status, 2) << second.err;
  EXPECT_NE(second.err.find("another cosim"), std::string::npos) << second.err;
}

TEST(HostileFolders, SecondRunWithForceIntoAFolderBeingWrittenRefused)
{
  Sandbox box;
  const pid_t first = spawn(box.dir(), long_run("out"));
  ASSERT_TRUE(wait_for([&] { return staging_checkpoint(box.dir()); }, 120));
  const Result second = run_at(box.dir(), quick({"run", ucs_case, "-o", "out", "--force"}));
  kill(first, SIGTERM);
  EXPECT_EQ(reap(first), 4);
  EXPECT_EQ(second.status, 2) << second.err;
  EXPECT_NE(second.err.find("another cosim"), std::string::npos) << second.err;
  EXPECT_TRUE(fs::exists(box.dir() / "out" / "checkpoint.h5")) << "the first run's checkpoint is published";
}

TEST(HostileFolders, StudyIntoTheWorkingFolderRefused)
{
  Sandbox box;
  box.write("c.prm", read_file(ucs_case));
  expect_refused(box.dir(), quick({"study", "c.prm", "--vary", "SPH/CSLH=1.2,1.3", "-o", ".", "--force"}),
                 {"working folder"});
}

TEST(HostileFolders, StudyForceRefusesAFolderCosimDidNotWrite)
{
  Sandbox box;
  box.write("mine/notes.txt", "keep\n");
  expect_refused(box.dir(), quick({"study", ucs_case, "--vary", "SPH/CSLH=1.2,1.3", "-o", "mine", "--force"}),
                 {"not written by cosim"});
}

TEST(HostileFolders, DiagnoseIntoTheWorkingFolderRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  expect_refused(box.dir(), {"diagnose", "data", "-o", ".", "--force"}, {"working folder"});
}

TEST(HostileFolders, DiagnoseIntoItsDataFolderRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  expect_refused(box.dir(), {"diagnose", "data", "-o", "data", "--force"}, {"holds the input"});
}

TEST(HostileFolders, DiagnoseForceRefusesAFolderCosimDidNotWrite)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  box.write("mine/notes.txt", "keep\n");
  expect_refused(box.dir(), {"diagnose", "data", "-o", "mine", "--force"}, {"not written by cosim"});
}

TEST(HostileFolders, DiagnoseEmptyOutputRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  expect_refused(box.dir(), {"diagnose", "data", "-o", ""}, {"empty"});
}

TEST(HostileFolders, DiagnoseDanglingSymlinkRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  fs::create_symlink(box.dir() / "nowhere", box.dir() / "out");
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"symbolic link"});
}

// ---------------------------------------------------------------- memory

TEST(HostileMemory, SpacingBeyondTheMachineRefusedUpFront)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--quiet", "--set", "SPH/Particle spacing=0.0001"},
                 {"SPH/Particle spacing", "particles", "GiB", "finest spacing that fits", "--memory-limit"});
}

TEST(HostileMemory, EstimateNamesTheTimeSteps)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--quiet", "--set", "SPH/Particle spacing=0.00012"}, {"time steps"});
}

TEST(HostileMemory, MemoryLimitOptionLowersTheLimit)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--quiet", "--memory-limit", "0.2"},
                 {"finest spacing that fits", "limit"});
}

TEST(HostileMemory, MemoryLimitMustBeANumber)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--quiet", "--memory-limit", "lots"}, {"--memory-limit", "not a finite"});
}

TEST(HostileMemory, SuggestedSpacingFitsTheLimit)
{
  Sandbox box;
  const Result r = run_at(box.dir(), {"run", ucs_case, "--quiet", "--memory-limit", "0.2", "-o", "out"});
  ASSERT_EQ(r.status, 2) << r.err;
  const auto at = r.err.find("fits is ");
  ASSERT_NE(at, std::string::npos) << r.err;
  const double dx = std::atof(r.err.c_str() + at + 8);
  ASSERT_GT(dx, 0.0025);
  // the spacing named passes the same check (then stops at once: Stop after steps)
  const Result again = run_at(box.dir(), {"run", ucs_case, "--quiet", "--memory-limit", "0.2", "-o", "out", "--set",
                                          "SPH/Particle spacing=" + std::to_string(dx * 1.01), "--set",
                                          "Output/Stop after steps=1"});
  EXPECT_NE(again.status, 2) << again.err;
}

TEST(HostileMemory, StudyRefusesBeforeTheFirstRun)
{
  Sandbox box;
  expect_refused(box.dir(), quick({"study", ucs_case, "--vary", "SPH/Particle spacing=0.005,0.0001", "-o", "s"}),
                 {"particles", "finest spacing"});
}

TEST(HostileMemory, DiagnoseCoupledSpacingRefusedUpFront)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  expect_refused(box.dir(), {"diagnose", "data", "--coupled-spacing", "1e-6", "-o", "out"},
                 {"--coupled-spacing", "particles", "finest spacing"});
}

// ---------------------------------------------------------------- checkpoints

TEST(HostileCheckpoint, FlippedByteInParticleDataRefused)
{
  Sandbox box;
  const fs::path file = interrupted_run(box.dir(), "out");
  flip_particle_byte(file);
  const Result r = run_at(box.dir(), {"run", "--restart", "out", "--quiet"});
  EXPECT_EQ(r.status, 2) << r.err;
  expect_one_short_line(r);
  EXPECT_NE(r.err.find("checksum"), std::string::npos) << r.err;
}

TEST(HostileCheckpoint, ReadCheckpointNamesTheDamagedDataset)
{
  Sandbox box;
  const fs::path file = interrupted_run(box.dir(), "out");
  flip_particle_byte(file);
  try
  {
    (void)app::read_checkpoint(file.string());
    FAIL() << "a damaged checkpoint was read";
  }
  catch (const coupling::InputError &e)
  {
    EXPECT_NE(std::string(e.what()).find("fails its checksum"), std::string::npos) << e.what();
  }
}

TEST(HostileCheckpoint, CheckpointOfAnotherCaseRefused)
{
  Sandbox box;
  interrupted_run(box.dir(), "a");
  interrupted_run(box.dir(), "b", {"--set", "Platens/Friction coefficient=0.2"});
  fs::copy_file(box.dir() / "a" / "checkpoint.h5", box.dir() / "b" / "checkpoint.h5",
                fs::copy_options::overwrite_existing);
  const Result r = run_at(box.dir(), {"run", "--restart", "b", "--quiet"});
  EXPECT_EQ(r.status, 2) << r.err;
  expect_one_short_line(r);
  EXPECT_NE(r.err.find("Friction coefficient"), std::string::npos) << "names what differs: " << r.err;
}

TEST(HostileCheckpoint, EditedUsedParametersRefused)
{
  Sandbox box;
  interrupted_run(box.dir(), "out");
  const fs::path prm = box.dir() / "out" / "used_parameters.prm";
  const std::string text = read_file(prm);
  const auto at = text.find("set Group");
  ASSERT_NE(at, std::string::npos);
  const auto eq = text.find('=', at), eol = text.find('\n', at);
  std::string edited = text;
  edited.replace(eq, eol - eq, "= M7");
  write_bytes(prm, edited);
  const Result r = run_at(box.dir(), {"run", "--restart", "out", "--quiet"});
  EXPECT_EQ(r.status, 2) << r.err;
  expect_one_short_line(r);
  EXPECT_NE(r.err.find("Rock/Group"), std::string::npos) << r.err;
}

TEST(HostileCheckpoint, UnchangedRestartStillWorks)
{
  Sandbox box;
  interrupted_run(box.dir(), "out");
  const Result r = run_at(box.dir(), {"run", "--restart", "out", "--quiet"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(read_file(box.dir() / "out" / ".cosim-result").find("complete"), std::string::npos);
}

TEST(HostileCheckpoint, CheckpointThatCannotBeWrittenEndsCleanly)
{
  // a file-size limit with SIGXFSZ ignored: writes fail with EFBIG as on a full disk
  Sandbox box;
  const Result r = run_at(box.dir(),
                          {"run", ucs_case, "-o", "out", "--quiet", "--set", "SPH/Particle spacing=0.005", "--set",
                           "Output/Checkpoint interval=20", "--set", "Loading/End strain=0.002"},
                          "trap '' XFSZ; ulimit -f 300;");
  EXPECT_EQ(r.status, 1) << r.err;
  expect_one_short_line(r);
  EXPECT_NE(r.err.find("disk full"), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(box.dir() / "out"));
  EXPECT_FALSE(any_hidden_staging(box.dir()));
}

TEST(HostileCheckpoint, ResultsThatCannotBeWrittenEndCleanly)
{
  Sandbox box;
  const Result r = run_at(box.dir(), quick({"run", ucs_case, "-o", "out"}), "trap '' XFSZ; ulimit -f 40;");
  EXPECT_EQ(r.status, 1) << r.err;
  expect_one_short_line(r);
  EXPECT_FALSE(any_hidden_staging(box.dir()));
}

TEST(HostileCheckpoint, InProcessCaseMismatchNamesTheKey)
{
  Sandbox box;
  const std::string file = (box.dir() / "c.h5").string();
  app::write_checkpoint(file, {{"body.x", {1.0, 2.0, 3.0}}},
                        "subsection SPH\n  set CSLH = 1.2\nend\n");
  const std::string now = "subsection SPH\n  set CSLH = 1.3\nend\n";
  try
  {
    (void)app::read_checkpoint(file, &now);
    FAIL() << "a checkpoint of another case was read";
  }
  catch (const coupling::InputError &e)
  {
    EXPECT_NE(std::string(e.what()).find("SPH/CSLH"), std::string::npos) << e.what();
  }
}

// ---------------------------------------------------------------- input

TEST(HostileInput, StudyEmptyValueListRefused)
{
  Sandbox box;
  expect_refused(box.dir(), quick({"study", ucs_case, "--vary", "SPH/CSLH=", "-o", "s"}), {"SPH/CSLH", "values"});
}

TEST(HostileInput, StudyEmptyKeyValueRefused)
{
  Sandbox box;
  expect_refused(box.dir(), quick({"study", ucs_case, "--key", "", "--values", "1.2", "-o", "s"}),
                 {"--key", "empty value"});
}

TEST(HostileInput, EmptyRestartValueRefused)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", "--restart", ""}, {"--restart", "empty value"});
}

TEST(HostileInput, EmptySetEqualsValueRefused)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--set="}, {"--set", "empty value"});
}

TEST(HostileInput, DiagnoseEmptyBicThresholdRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  expect_refused(box.dir(), {"diagnose", "data", "--bic-threshold", ""}, {"--bic-threshold", "empty value"});
}

TEST(HostileInput, DiagnoseSimulationsNotAWholeNumberRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  for (const char *v : {"0", "2.5", "101", "nan"})
    expect_refused(box.dir(), {"diagnose", "data", "--simulations", v}, {"--simulations", "whole number"});
}

TEST(HostileInput, DataTableWithUtf8BomAccepted)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", "", "\xEF\xBB\xBF");
  const Result r = run_at(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}));
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST(HostileInput, DataTableWithUtf16Refused)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", "", "\xFF\xFE");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:1", "UTF-16"});
}

TEST(HostileInput, NulByteInDataTableNamesTheLine)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", std::string("M1,0,0,97.07,0.28,,,282.18,15.43\0junk", 37));
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:3", "NUL"});
}

TEST(HostileInput, Latin1InDataTableNamesTheLine)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", "M1,0,0,97.07,0.28,,,282.18,15.43 \xB0");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:3", "not UTF-8"});
}

TEST(HostileInput, HexNumberInDataTableRefused)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", "M1,0,0,0x1.8p6,0.28,,,282.18,15.43");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:3", "E_GPa", "decimal"});
}

TEST(HostileInput, HugeBadCellIsClipped)
{
  Sandbox box;
  const std::string data =
    data_copy(box.dir() / "data", "M1,0,0," + std::string(5u << 20, '9') + "x,0.28,,,282.18,15.43");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:3", "bytes)"});
}

TEST(HostileInput, ImplausibleTableValueBlamedOnTheTable)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", "M1,0,0,5000,0.28,,,282.18,15.43");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:3", "E_GPa"});
}

TEST(HostileInput, ImplausibleStrengthBlamedOnTheTable)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "data", "M1,0,0,97.07,0.28,,,2e9,15.43");
  expect_refused(box.dir(), quick({"run", ucs_case, "-o", "out", "--set", "Rock/Data directory=" + data}),
                 {"table3_fitted_parameters.csv:3", "UCS_MPa"});
}

TEST(HostileInput, DiagnoseMaterialWithBomAccepted)
{
  Sandbox box;
  diagnose_data(box.dir() / "data", "\xEF\xBB\xBF");
  const Result r = run_at(box.dir(), {"diagnose", "data", "-o", "out"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::exists(box.dir() / "out" / "diagnosis.json"));
}

TEST(HostileInput, DiagnoseMaterialWithNulRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  write_bytes(box.dir() / "data" / "material.csv",
              "group,E_GPa,nu,UCS_MPa,BTS_MPa\nM1,97" + std::string(1, '\0') + ".07,0.28,282.18,15.43\n");
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"material.csv:2", "NUL"});
}

TEST(HostileInput, DiagnoseCurveWithZeroForcesRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  write_bytes(box.dir() / "data" / "curves" / "ucs1.csv", curve({0, 0, 0, 0, 0, 0, 0}));
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"ucs1.csv", "never positive"});
}

TEST(HostileInput, DiagnoseCurveWithNegativeForcesRefused)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  write_bytes(box.dir() / "data" / "curves" / "ucs1.csv", curve({0, -10, -20, -30, -40, -50, -60}));
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"ucs1.csv", "positive force"});
}

TEST(HostileInput, DiagnoseCurveWithOneNegativeRowNamesTheLine)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  write_bytes(box.dir() / "data" / "curves" / "ucs1.csv", curve({0, 100, 200, -150, 300, 350, 360}));
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"ucs1.csv:10", "negative"});
}

TEST(HostileInput, DiagnoseCurveHugeHeaderValueClipped)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  std::string c = curve({0, 100, 200, 300, 400, 500});
  c.replace(c.find("UCS"), 3, std::string(1u << 20, 'U'));
  write_bytes(box.dir() / "data" / "curves" / "ucs1.csv", c);
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"ucs1.csv", "test"});
}

TEST(HostileInput, DiagnoseCurveWithCrlfAndBomAcceptedUpToTheForces)
{
  // a Windows-saved curve with all-zero forces: read past its header (BOM, CRLF) to the force check
  Sandbox box;
  diagnose_data(box.dir() / "data");
  write_bytes(box.dir() / "data" / "curves" / "ucs1.csv",
              "\xEF\xBB\xBF" + replace_all(curve({0, 0, 0, 0, 0, 0}), "\n", "\r\n"));
  expect_refused(box.dir(), {"diagnose", "data", "-o", "out"}, {"ucs1.csv", "never positive"});
}

TEST(HostileInput, HugeUnknownOptionClipped)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--" + std::string(100000, 'x')}, {"unknown option", "bytes)"});
}

TEST(HostileInput, HugeUnknownSubcommandClipped)
{
  Sandbox box;
  expect_refused(box.dir(), {std::string(100000, 'r')}, {"unknown subcommand", "bytes)"});
}

TEST(HostileInput, NonUtf8OptionGivesUtf8Message)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "--fo\xFF\xFE"}, {"unknown option", "\\xFF"});
}

TEST(HostileInput, NonUtf8SecondCaseFileGivesUtf8Message)
{
  Sandbox box;
  expect_refused(box.dir(), {"run", ucs_case, "c\xC3.prm"}, {"second case file", "\\xC3"});
}

TEST(HostileInput, HugeStudyVaryClipped)
{
  Sandbox box;
  expect_refused(box.dir(), {"study", ucs_case, "--vary", std::string(100000, 'k')}, {"--vary", "bytes)"});
}

TEST(HostileInput, DiagnoseHugeSecondFolderClipped)
{
  Sandbox box;
  diagnose_data(box.dir() / "data");
  expect_refused(box.dir(), {"diagnose", "data", std::string(100000, 'd')}, {"one DATA_DIR", "bytes)"});
}

// Case files: read through diagnose::read_text_file (a byte-order mark is dropped), an extension
// other than .prm or .json refused in cosim's own words, `#` in a value kept across
// used_parameters.prm and --restart.
TEST(HostileCaseFile, CaseFileWithBomAccepted)
{
  Sandbox box;
  box.write("c.prm", "\xEF\xBB\xBF" + read_file(ucs_case));
  EXPECT_EQ(run_at(box.dir(), quick({"run", "c.prm", "-o", "out"})).status, 0);
}

TEST(HostileInput, HexNumberInCaseFileIsOneShortLine)
{
  Sandbox box;
  std::string text = read_file(ucs_case);
  const auto at = text.find("set CSLH");
  ASSERT_NE(at, std::string::npos);
  text.replace(text.find('=', at), text.find('\n', at) - text.find('=', at), "= 0x1p0");
  box.write("c.prm", text);
  expect_refused(box.dir(), quick({"run", "c.prm", "-o", "out"}), {"SPH/CSLH", "0x1p0"});
}

TEST(HostileInput, HexNumberInSetIsOneShortLine)
{
  Sandbox box;
  expect_refused(box.dir(), quick({"run", ucs_case, "--set", "SPH/CSLH=0x1p0"}), {"SPH/CSLH", "0x1p0"});
}

TEST(HostileCaseFile, UnknownExtensionIsOneShortLine)
{
  Sandbox box;
  box.write("c.txt", read_file(ucs_case));
  const Result r = run_at(box.dir(), quick({"run", "c.txt", "-o", "out"}));
  EXPECT_EQ(r.status, 2);
  expect_one_short_line(r);
  EXPECT_NE(r.err.find(".prm"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Stacktrace"), std::string::npos) << "a message, not a library dump: " << r.err;
}

TEST(HostileCaseFile, HashInDataDirectorySurvivesRestart)
{
  Sandbox box;
  const std::string data = data_copy(box.dir() / "d#1");
  interrupted_run(box.dir(), "out", {"--set", "Rock/Data directory=" + data});
  const Result r = run_at(box.dir(), {"run", "--restart", "out", "--quiet"});
  EXPECT_EQ(r.status, 0) << r.err;
}

// ---------------------------------------------------------------- signals

TEST(HostileSignals, SighupStopsWithACheckpoint)
{
  Sandbox box;
  const pid_t pid = spawn(box.dir(), long_run("out"));
  ASSERT_TRUE(wait_for([&] { return staging_checkpoint(box.dir()); }, 120));
  kill(pid, SIGHUP);
  EXPECT_EQ(reap(pid), 4);
  EXPECT_TRUE(fs::exists(box.dir() / "out" / "checkpoint.h5"));
  EXPECT_FALSE(any_hidden_staging(box.dir()));
}

TEST(HostileSignals, SighupRunContinuesFromItsCheckpoint)
{
  Sandbox box;
  std::vector<std::string> args = long_run("out");
  args.push_back("--set");
  args.push_back("Loading/End strain=0.001"); // the last --set wins: a short run to finish
  const pid_t pid = spawn(box.dir(), args);
  ASSERT_TRUE(wait_for([&] { return staging_checkpoint(box.dir()); }, 120));
  kill(pid, SIGHUP);
  ASSERT_EQ(reap(pid), 4);
  const Result r = run_at(box.dir(), {"run", "--restart", "out", "--quiet"});
  EXPECT_EQ(r.status, 0) << r.err;
}

TEST(HostileSignals, StudyReportsAnInterruption)
{
  Sandbox box;
  const pid_t pid = spawn(box.dir(), {"study", ucs_case, "--vary", "SPH/CSLH=1.2,1.3", "-o", "s", "--quiet", "--set",
                                      "SPH/Particle spacing=0.005", "--set", "Loading/End strain=0.02", "--set",
                                      "Output/Checkpoint interval=20", "--set", "SPH/Threads=1"});
  ASSERT_TRUE(wait_for([&] { return staging_checkpoint(box.dir()); }, 120));
  kill(pid, SIGTERM);
  EXPECT_EQ(reap(pid), 4) << "an interruption, not an unstable run";
  const std::string err = read_file(box.dir() / "spawn-err.txt");
  EXPECT_NE(err.find("interrupted"), std::string::npos) << err;
  EXPECT_EQ(err.find("unstable"), std::string::npos) << err;
  EXPECT_NE(read_file(box.dir() / "s" / "study.csv").find("interrupted"), std::string::npos);
  // the restart it names exists
  const auto at = err.find("--restart ");
  ASSERT_NE(at, std::string::npos) << err;
  const std::string folder = err.substr(at + 10, err.find('\n', at) - at - 10);
  EXPECT_TRUE(fs::exists(fs::path(folder) / "checkpoint.h5")) << folder;
}

TEST(HostileSignals, StudySighupIsAnInterruption)
{
  Sandbox box;
  const pid_t pid = spawn(box.dir(), {"study", ucs_case, "--vary", "SPH/CSLH=1.2,1.3", "-o", "s", "--quiet", "--set",
                                      "SPH/Particle spacing=0.005", "--set", "Loading/End strain=0.02", "--set",
                                      "Output/Checkpoint interval=20", "--set", "SPH/Threads=1"});
  ASSERT_TRUE(wait_for([&] { return staging_checkpoint(box.dir()); }, 120));
  kill(pid, SIGHUP);
  EXPECT_EQ(reap(pid), 4);
  EXPECT_TRUE(fs::exists(box.dir() / "s" / "study.csv"));
}

// ---------------------------------------------------------------- the text reader itself

TEST(HostileText, BomAndCrlfNormalised)
{
  EXPECT_EQ(diagnose::normalise_text("\xEF\xBB\xBF" "a,b\r\n1,2\r3\n", "f.csv"), "a,b\n1,2\n3\n");
}

TEST(HostileText, NulNamesTheLine)
{
  try
  {
    (void)diagnose::normalise_text(std::string("a\nb\nc\0d\n", 8), "f.csv");
    FAIL();
  }
  catch (const coupling::InputError &e)
  {
    EXPECT_NE(std::string(e.what()).find("f.csv:3"), std::string::npos) << e.what();
  }
}

TEST(HostileText, OverlongUtf8Refused)
{
  EXPECT_TRUE(diagnose::invalid_utf8_at("ok \xC0\xAF").has_value());
  EXPECT_TRUE(diagnose::invalid_utf8_at("\xED\xA0\x80").has_value()); // a surrogate
  EXPECT_FALSE(diagnose::invalid_utf8_at("\xE2\x80\x94 \xF0\x9F\x98\x80").has_value());
}

TEST(HostileText, ClipShowsBytesAndLength)
{
  const std::string c = diagnose::clip(std::string("a\0b", 3) + std::string(1000, 'x'));
  EXPECT_NE(c.find("\\x00"), std::string::npos);
  EXPECT_NE(c.find("(1003 bytes)"), std::string::npos);
  EXPECT_LT(c.size(), 260u);
}

TEST(HostileText, DecimalNumbersOnly)
{
  for (const char *yes : {"1", "-1.5", "+.5", "2e-3", "1.E5"})
    EXPECT_TRUE(diagnose::is_decimal_number(yes)) << yes;
  for (const char *no : {"0x10", "inf", "nan", "1e", ".", "1 2", ""})
    EXPECT_FALSE(diagnose::is_decimal_number(no)) << no;
  EXPECT_FALSE(diagnose::parse_finite_double("0x1p3").has_value());
}

TEST(HostileText, PrmHashEscapeRoundTrips)
{
  const std::string path = "/data/run#1/x";
  const std::string line = "  set Data directory = " + diagnose::escape_prm_value(path) + "   # default: cases/data";
  EXPECT_EQ(diagnose::strip_prm_comment(line), "  set Data directory = " + path);
}
