// Distributed runs through the built cosim under mpirun: the history of an N-rank run (N = 1 to 4)
// is the serial one (UCS, BTS, CTCS, indentation, linear cutting), a checkpoint written on 2
// ranks continues on 3 as if never interrupted (UCS, linear cutting), and what one rank refuses
// every rank refuses, with one line and nothing written.
//
// Tolerances: every rank computes its particles' forces from the same neighbours in the same
// order as the serial body (sph::Domain, sph::Body::set_chunks), so the particles move by the
// serial bits; only sums over the particles (platen forces, energies, gauge strains) are added
// rank by rank, a different rounding of ~1e-16 of the sum. history.csv prints 9 significant
// digits, so each column may differ by 1e-9 of its largest magnitude, or by one printed digit
// where a value lies at a rounding boundary (same_history), and no more, but for the
// dissipated energy: it accumulates, step by step, sums over the pairs of viscous and hourglass
// powers of both signs, whose rounding is relative to the sum of their magnitudes, not to the
// result (3.8e-9 of the column's largest value measured with a 2 mm UCS over 2,337 steps on 2
// ranks): 1e-6. The peak stress and peak force (summary.json) are held to 1e-6 relative as the
// specification of distributed runs asks. The cutter cases' cutter is rigid (prescribed motion):
// the particles move by the serial bits there too, so which particles fail and leave the contact
// as chip is the serial run's exactly.
#include "subprocess.h"

#include <app/checkpoint.h>

#include <gtest/gtest.h>
#include <hdf5.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <unistd.h>

namespace
{
  using namespace cosim_test;

  /// A parsed history.csv: its header and rows.
  struct History
  {
    std::vector<std::string>         columns;
    std::vector<std::vector<double>> rows;
  };

  History read_history(const fs::path &file)
  {
    History            h;
    std::istringstream in(read_file(file));
    std::string        line;
    std::getline(in, line);
    std::istringstream header(line);
    for (std::string c; std::getline(header, c, ',');)
      h.columns.push_back(c);
    while (std::getline(in, line))
    {
      std::vector<double> row;
      std::istringstream  cells(line);
      for (std::string c; std::getline(cells, c, ',');)
        row.push_back(std::stod(c));
      h.rows.push_back(row);
    }
    return h;
  }

  /// Every column of `b` within 1e-9 of the largest |value| of that column of `a` (the dissipated
  /// energy within 1e-6: see the file comment), or within one unit of the ninth significant digit
  /// of that largest value: a value whose sums differ in the last bits prints as the neighbouring
  /// nine-digit number where it lies at a rounding boundary (a CTCS axial gauge strain of
  /// 0.00268064978 against 0.00268064977: 3.7e-9 of the column, one printed digit).
  ::testing::AssertionResult same_history(const History &a, const History &b)
  {
    if (a.columns != b.columns || a.rows.size() != b.rows.size())
      return ::testing::AssertionFailure() << a.rows.size() << " rows against " << b.rows.size();
    for (std::size_t c = 0; c < a.columns.size(); ++c)
    {
      double scale = 0;
      for (const auto &r : a.rows)
        scale = std::max(scale, std::abs(r[c]));
      const double relative = a.columns[c] == "dissipated_energy_J" ? 1e-6 : 1e-9;
      // (the printed unit with a margin of 1 % for the decimal-to-binary conversion)
      const double digit =
        scale > 0 ? 1.01 * std::pow(10.0, std::floor(std::log10(scale)) - 8.0) : 0.0;
      const double tolerance = std::max(relative * scale, digit);
      for (std::size_t k = 0; k < a.rows.size(); ++k)
        if (std::abs(a.rows[k][c] - b.rows[k][c]) > tolerance)
          return ::testing::AssertionFailure()
                 << a.columns[c] << " differs at row " << k << ": " << a.rows[k][c] << " against "
                 << b.rows[k][c];
    }
    return ::testing::AssertionSuccess();
  }

  /// One particle dataset of results.h5 (`snapshot`: e.g. "000003"), read as doubles; empty
  /// when it does not exist.
  std::vector<double> particle_field(const fs::path &h5, const std::string &snapshot, const std::string &field)
  {
    std::vector<double> values;
    const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    if (file < 0)
      return values;
    const std::string name = "/snapshots/" + snapshot + "/particles/" + field;
    if (H5Lexists(file, "/snapshots", H5P_DEFAULT) > 0 &&
        H5Lexists(file, ("/snapshots/" + snapshot).c_str(), H5P_DEFAULT) > 0)
    {
      const hid_t set = H5Dopen2(file, name.c_str(), H5P_DEFAULT);
      if (set >= 0)
      {
        const hid_t space = H5Dget_space(set);
        values.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(space)));
        if (!values.empty())
          H5Dread(set, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values.data());
        H5Sclose(space);
        H5Dclose(set);
      }
    }
    H5Fclose(file);
    return values;
  }

  /// results.h5 of `b` holds the snapshots of `a`, every particle field of every snapshot within
  /// 1e-9 of the field's largest magnitude (the owned particles move by the serial bits; measured:
  /// equal to the bit on 3 ranks). The ranks write their rows together (parallel HDF5), so this
  /// also checks that each particle lands in its place.
  ::testing::AssertionResult same_particles(const fs::path &a, const fs::path &b)
  {
    const char *fields[] = {"position", "velocity", "displacement", "stress", "von_mises",
                            "mean_stress_compression_positive", "plastic_strain", "damage",
                            "failure_mode"};
    std::size_t k = 0;
    for (;; ++k)
    {
      char snapshot[16];
      std::snprintf(snapshot, sizeof snapshot, "%06zu", k);
      const std::vector<double> pa = particle_field(a, snapshot, "position");
      if (pa.empty())
        break;
      for (const char *f : fields)
      {
        const std::vector<double> x = particle_field(a, snapshot, f), y = particle_field(b, snapshot, f);
        if (x.size() != y.size())
          return ::testing::AssertionFailure() << "snapshot " << snapshot << " " << f << ": " << y.size()
                                               << " values against " << x.size();
        double scale = 0, worst = 0;
        for (std::size_t i = 0; i < x.size(); ++i)
        {
          scale = std::max(scale, std::abs(x[i]));
          worst = std::max(worst, std::abs(x[i] - y[i]));
        }
        if (worst > 1e-9 * scale)
          return ::testing::AssertionFailure() << "snapshot " << snapshot << " " << f << " differs by " << worst;
      }
    }
    char next[16];
    std::snprintf(next, sizeof next, "%06zu", k);
    if (k < 2 || !particle_field(b, next, "position").empty())
      return ::testing::AssertionFailure() << k << " snapshots in the serial run, or more in the other";
    return ::testing::AssertionSuccess();
  }

  nlohmann::json summary(const fs::path &folder)
  {
    return nlohmann::json::parse(read_file(folder / "summary.json"));
  }

  /// `cosim ARGS` under mpirun with `n_ranks` ranks (oversubscribed: CI has 2 cores; as root,
  /// Open MPI needs --allow-run-as-root), or without mpirun for n_ranks = 0.
  Result run_ranks(const Sandbox &box, const int n_ranks, const std::vector<std::string> &args)
  {
    if (n_ranks == 0)
      return run_cosim(box, args);
    const fs::path capture = fs::path(box.dir().string() + ".capture");
    fs::create_directories(capture);
    std::string command = "cd " + shell_quote(box.dir().string()) + " && " +
                          shell_quote(COSIM_MPIEXEC) + (geteuid() == 0 ? " --allow-run-as-root" : "") +
                          " --oversubscribe -np " + std::to_string(n_ranks) + " " +
                          shell_quote(cosim_binary());
    for (const auto &a : args)
      command += " " + shell_quote(a);
    command += " >" + shell_quote((capture / "out").string()) + " 2>" +
               shell_quote((capture / "err").string());
    const int raw = std::system(command.c_str());
    Result    r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out    = read_file(capture / "out");
    r.err    = read_file(capture / "err");
    return r;
  }

  /// Lines of `text` that cosim wrote (mpirun adds its own notice of a non-zero exit).
  std::vector<std::string> cosim_lines(const std::string &text)
  {
    std::vector<std::string> lines;
    std::istringstream       in(text);
    for (std::string line; std::getline(in, line);)
      if (line.rfind("cosim:", 0) == 0)
        lines.push_back(line);
    return lines;
  }

  /// One thread per rank: the comparison is of ranks, not threads. 5 mm spacing unless `extra`
  /// gives one.
  std::vector<std::string> small_case(const std::string &case_file, const std::string &folder,
                                      std::vector<std::string> extra = {})
  {
    const bool spacing         = std::any_of(extra.begin(), extra.end(), [](const std::string &e) {
      return e.rfind("SPH/Particle spacing=", 0) == 0;
    });
    std::vector<std::string> a = {"run",     source(case_file), "-o",           folder,
                                  "--quiet", "--set",           "SPH/Threads=1"};
    if (!spacing)
      a.insert(a.end(), {"--set", "SPH/Particle spacing=0.005"});
    for (const auto &e : extra)
      a.insert(a.end(), {"--set", e});
    return a;
  }

  /// Runs `case_file` with `extra` serially (into `box`/serial) and on each of `ranks`: the same
  /// history, steps, particles and peaks; each particle owned once. Returns the serial summary.
  nlohmann::json expect_serial_result(const Sandbox &box, const std::string &case_file,
                                      const std::vector<std::string> &extra,
                                      const std::vector<int> &ranks)
  {
    const Result serial = run_ranks(box, 0, small_case(case_file, "serial", extra));
    EXPECT_EQ(serial.status, 0) << serial.err;
    if (serial.status != 0)
      return {};
    const History        reference = read_history(box.dir() / "serial" / "history.csv");
    const nlohmann::json s         = summary(box.dir() / "serial");
    EXPECT_GT(reference.rows.size(), 10u);
    if (reference.rows.size() <= 10u)
      return s;
    for (const int n : ranks)
    {
      SCOPED_TRACE(std::to_string(n) + " ranks");
      const std::string folder = "ranks" + std::to_string(n);
      const Result      r      = run_ranks(box, n, small_case(case_file, folder, extra));
      EXPECT_EQ(r.status, 0) << r.err;
      if (r.status != 0)
        continue;
      EXPECT_TRUE(same_history(reference, read_history(box.dir() / folder / "history.csv")));
      EXPECT_TRUE(same_particles(box.dir() / "serial" / "results.h5", box.dir() / folder / "results.h5"));
      const nlohmann::json m = summary(box.dir() / folder);
      EXPECT_EQ(m["n_steps"], s["n_steps"]);
      EXPECT_EQ(m["n_particles"], s["n_particles"]);
      const double peak = s["peak_stress_MPa"];
      EXPECT_NEAR(m["peak_stress_MPa"].get<double>(), peak, 1e-6 * peak);
      const double peak_force = s["peak_force_kN"];
      EXPECT_GT(peak_force, 0.0);
      EXPECT_NEAR(m["peak_force_kN"].get<double>(), peak_force, 1e-6 * peak_force);
      for (const char *count : {"n_chip_particles_released", "n_fixed_particles"})
        if (s.contains(count))
          EXPECT_EQ(m[count], s[count]) << count;
      EXPECT_EQ(m["n_ranks"], n);
      std::size_t owned = 0;
      for (const auto &c : m["particles_per_rank"])
      {
        EXPECT_GT(c.get<std::size_t>(), 0u);
        owned += c.get<std::size_t>();
      }
      EXPECT_EQ(owned, s["n_particles"].get<std::size_t>()); // each particle owned once
      if (n > 1)
      {
        // the ranks' waits are parts of the run loop, which wall_seconds contains: a wait counted
        // outside it (set-up, output after the loop) or twice could exceed it
        const double least = m["mpi_wait_seconds_min"], most = m["mpi_wait_seconds_max"];
        EXPECT_GE(least, 0.0);
        EXPECT_LE(least, most);
        EXPECT_LE(most, m["wall_seconds"].get<double>());
      }
    }
    return s;
  }

  /// A rigid cone pressed 6 mm into a 30 mm cube at 3 mm spacing (1,000 particles, the smallest
  /// block and penetration the case's checks allow at that spacing), sharp, at TSSFAC 0.9 and
  /// the intact friction angle after failure, as tests/app/cutting_restart_test.cc runs it, but
  /// at 32 m/s (373 steps): a test of the split, not of the physics; particles fail under the
  /// tip.
  const std::vector<std::string> small_indentation = {"SPH/Particle spacing=0.003",
                                                      "Cutter/Tip radius=0",
                                                      "SPH/TSSFAC=0.9",
                                                      "Cutter/Penetration=0.006",
                                                      "Cutter/Speed=32",
                                                      "Cutter/Block length=0.03",
                                                      "Cutter/Block width=0.03",
                                                      "Cutter/Block height=0.03",
                                                      "Output/History rows=40",
                                                      "Output/Snapshots=2",
                                                      "Rock/Residual friction angle="};

  /// A rigid 30 mm disc, 6 mm deep, 25 mm across a 33 x 30 x 30 mm block at 3 mm spacing (1,100
  /// particles; the shortest cut and block the checks allow for this disc) at 96 m/s (607 steps;
  /// the split is tested, not the physics): rock fails from about step 150 on and leaves the
  /// contact as chip.
  const std::vector<std::string> small_cut = {
    "SPH/Particle spacing=0.003", "Cutter/Speed=96",          "Cutter/Disc diameter=0.03",
    "Cutter/Tip width=0.006",     "Cutter/Penetration=0.006", "Cutter/Cut length=0.025",
    "Cutter/Block length=0.033",  "Cutter/Block width=0.03",  "Cutter/Block height=0.03",
    "Output/History rows=40",     "Output/Snapshots=2"};
} // namespace

TEST(MpiRun, UcsOnOneToFourRanksGivesTheSerialHistory)
{
  Sandbox box;
  expect_serial_result(box, "cases/ucs/ucs.prm", {}, {1, 2, 3, 4});
}

TEST(MpiRun, BtsOnElasticPlatensGivesTheSerialPeak)
{
  // the kinematic contacts on an elastic platen's face nodes are solved together across the
  // ranks (PenaltyContact::set_reduction): the disc's ranks split each line of contact, so each
  // rank's particles push nodes that the other's push too. Each rank alone gave 17.12 MPa and
  // 525 steps on 2 ranks against 17.22 MPa and 533 steps serially. Together the nodes' sums are
  // taken in another order than the serial one: the same steps and peak to 1e-6 (measured 5e-9),
  // not the same bits
  Sandbox box;
  const std::vector<std::string> extra = {"Test/Length=0.05", "Platens/Model=elastic"};
  const Result serial = run_ranks(box, 0, small_case("cases/bts/bts-round.prm", "serial", extra));
  ASSERT_EQ(serial.status, 0) << serial.err;
  const nlohmann::json s = summary(box.dir() / "serial");
  const double peak      = s["peak_stress_MPa"];
  for (const int n : {2, 3})
  {
    SCOPED_TRACE(std::to_string(n) + " ranks");
    const std::string folder = "ranks" + std::to_string(n);
    const Result r           = run_ranks(box, n, small_case("cases/bts/bts-round.prm", folder, extra));
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json m = summary(box.dir() / folder);
    EXPECT_EQ(m["n_steps"], s["n_steps"]);
    EXPECT_NEAR(m["peak_stress_MPa"].get<double>(), peak, 1e-6 * peak);
  }
}

TEST(MpiRun, BtsOnOneToFourRanksGivesTheSerialHistory)
{
  // a 50 mm x 50 mm disc, so that 5 mm is fine enough (800 particles)
  Sandbox box;
  expect_serial_result(box, "cases/bts/bts-round.prm", {"Test/Length=0.05"}, {1, 2, 3, 4});
}

TEST(MpiRun, CtcsOnOneToFourRanksGivesTheSerialHistory)
{
  // the confining pressure on the owned surface particles, its work summed over the ranks; a
  // 50 mm x 50 mm specimen, so that 5 mm is fine enough (800 particles)
  Sandbox box;
  expect_serial_result(box, "cases/ctcs/ctcs.prm", {"Test/Length=0.05"}, {1, 2, 3, 4});
}

TEST(MpiRun, IndentationOnOneToFourRanksGivesTheSerialHistory)
{
  Sandbox box;
  const nlohmann::json s =
    expect_serial_result(box, "cases/indentation/indentation.prm", small_indentation, {1, 2, 3, 4});
  EXPECT_GT(s["peak_normal_force_kN"].get<double>(), 0.0);
}

namespace
{
  /// The same arrays: the per-particle ones (a multiple of the particle count long) equal to the
  /// bit, as the particles move by the serial bits (a row in the wrong place differs by a
  /// particle's whole state); every other value (accounts summed over the ranks, the platens
  /// they drive, the history rows) within 1e-6 of its array's largest |value|, the tolerance of
  /// the history comparison and for the same reason (see the file comment).
  void expect_same_state(const coupling::StateArrays &serial, const coupling::StateArrays &split)
  {
    ASSERT_EQ(serial.size(), split.size());
    ASSERT_EQ(serial.count("body.x"), 1u);
    const std::size_t n = serial.at("body.x").size() / 3;
    for (const auto &[name, a] : serial)
    {
      SCOPED_TRACE(name);
      ASSERT_EQ(split.count(name), 1u);
      const std::vector<double> &b = split.at(name);
      ASSERT_EQ(a.size(), b.size());
      if (!a.empty() && a.size() % n == 0)
      {
        EXPECT_TRUE(a == b);
        continue;
      }
      double scale = 0, worst = 0;
      for (std::size_t k = 0; k < a.size(); ++k)
      {
        scale = std::max(scale, std::abs(a[k]));
        worst = std::max(worst, std::abs(a[k] - b[k]));
      }
      EXPECT_LE(worst, 1e-6 * scale);
    }
  }

  /// `case_file` with `extra` stopped after `stop_after` steps on 2 ranks (exit 4, checkpoint.h5
  /// of global arrays) and continued on 3 gives the serial history and steps (the serial run:
  /// `box`/serial, run here unless it is there).
  void expect_restart_on_three(const Sandbox &box, const std::string &case_file,
                               const std::vector<std::string> &extra, const int stop_after)
  {
    if (!fs::exists(box.dir() / "serial" / "summary.json"))
    {
      const Result serial = run_ranks(box, 0, small_case(case_file, "serial", extra));
      ASSERT_EQ(serial.status, 0) << serial.err;
    }
    std::vector<std::string> stop = extra;
    stop.push_back("Output/Stop after steps=" + std::to_string(stop_after));
    const Result first = run_ranks(box, 2, small_case(case_file, "split", stop));
    ASSERT_EQ(first.status, 4) << first.err;
    ASSERT_TRUE(fs::exists(box.dir() / "split" / "checkpoint.h5"));
    // the checkpoint both ranks wrote holds the serial run's state at that step: every array,
    // the particles' rows in the serial order
    const Result serial_stop = run_ranks(box, 0, small_case(case_file, "serial_stop", stop));
    ASSERT_EQ(serial_stop.status, 4) << serial_stop.err;
    expect_same_state(app::read_checkpoint((box.dir() / "serial_stop" / "checkpoint.h5").string()),
                      app::read_checkpoint((box.dir() / "split" / "checkpoint.h5").string()));
    const Result second = run_ranks(box, 3, {"run", "--restart", "split", "--quiet"});
    ASSERT_EQ(second.status, 0) << second.err;
    EXPECT_TRUE(same_history(read_history(box.dir() / "serial" / "history.csv"),
                             read_history(box.dir() / "split" / "history.csv")));
    // the 2-rank run's snapshots up to the checkpoint copied, the 3-rank run's written after them
    EXPECT_TRUE(same_particles(box.dir() / "serial" / "results.h5", box.dir() / "split" / "results.h5"));
    EXPECT_EQ(summary(box.dir() / "split")["n_steps"], summary(box.dir() / "serial")["n_steps"]);
    EXPECT_EQ(summary(box.dir() / "split")["n_ranks"], 3);
  }
} // namespace

TEST(MpiRun, CheckpointOfTwoRanksContinuesOnThree)
{
  Sandbox box;
  expect_restart_on_three(box, "cases/ucs/ucs.prm", {}, 400);
}

TEST(MpiRun, LinearCutOnOneToFourRanksAndAfterARestartGivesTheSerialHistoryAndChip)
{
  Sandbox box;
  const nlohmann::json s =
    expect_serial_result(box, "cases/linear-cutting/linear-cutting.prm", small_cut, {1, 2, 3, 4});
  EXPECT_GT(s["n_chip_particles_released"].get<double>(), 0.0)
    << "the cut must release chip, or the chip flags are not tested across ranks";
  // stopped on 2 ranks at step 300, with chip released (the chip flags and the contact forces
  // they read are then part of the checkpoint), continued on 3
  expect_restart_on_three(box, "cases/linear-cutting/linear-cutting.prm", small_cut, 300);
}

// An unstable distributed run gathers its last good state from every rank, failure modes
// included (they were written as zeros). The case: a very ductile heterogeneous rock (M1 with
// Table 4's c, phi, G_I
// 10^4 J/m^2, Weibull m 10 on 5 mm cells, rock 2) in an 80 x 40 mm cylinder at 4 mm, friction
// 0.5, whose top rim particle is squeezed out after the rock has begun to fail (docs/
// limitations.md); serially unstable at step 565 with 1,748 softened particles. The particles
// move by the serial bits on 2 ranks, so the last good state's failure modes are the serial ones.
TEST(MpiRun, AnUnstableRunGathersItsLastGoodFailureModes)
{
  Sandbox box;
  const std::vector<std::string> ductile = {
    "Test/Diameter=0.08", "Test/Length=0.04", "SPH/Particle spacing=0.004",
    "Platens/Friction coefficient=0.5", "Rock/Strength scatter=10", "Rock/Scatter length=0.005",
    "Rock/Softening law=fracture energy", "Rock/Fracture energy=10000", "Rock/Scatter seed=2",
    "Loading/End strain=0.01", "Output/Snapshots=2", "Rock/Strength parameters=calibrated"};
  const Result serial = run_ranks(box, 0, small_case("cases/ucs/ucs.prm", "serial", ductile));
  ASSERT_EQ(serial.status, 3) << "the case must go unstable (pick another if it no longer does): "
                              << serial.err;
  const Result two = run_ranks(box, 2, small_case("cases/ucs/ucs.prm", "two", ductile));
  ASSERT_EQ(two.status, 3) << two.err;
  const auto modes = [&](const std::string &folder) {
    return particle_field(box.dir() / (folder + ".failed") / "last_good_state.h5", "000000",
                          "failure_mode");
  };
  const std::vector<double> a = modes("serial"), b = modes("two");
  // 3,160 particles; the rock has failed (measured: 1,065 tensile, 664 shear, 19 crushed: 1,748
  // failed; 1,000 is the bound that tells failure modes from the zeros once written)
  ASSERT_EQ(a.size(), 3160u);
  EXPECT_GT(std::count_if(a.begin(), a.end(), [](const double m) { return m > 0; }), 1000);
  EXPECT_EQ(a, b);
}

TEST(MpiRun, EveryRankRefusesAlike)
{
  Sandbox box;
  // bad input: one line, printed once, exit 2, nothing written
  const Result bad = run_ranks(box, 2, small_case("cases/ucs/ucs.prm", "bad", {"SPH/CSLH=-1"}));
  EXPECT_EQ(bad.status, 2);
  EXPECT_EQ(cosim_lines(bad.err).size(), 1u) << bad.err;
  EXPECT_FALSE(fs::exists(box.dir() / "bad"));
  // the updated Lagrangian forms need particles to migrate between ranks: refused
  const Result ul = run_ranks(box, 2, small_case("cases/ucs/ucs.prm", "ul", {"SPH/FORM=1"}));
  EXPECT_EQ(ul.status, 2);
  const auto lines = cosim_lines(ul.err);
  ASSERT_EQ(lines.size(), 1u) << ul.err;
  EXPECT_NE(lines[0].find("one MPI rank only"), std::string::npos) << lines[0];
  EXPECT_FALSE(fs::exists(box.dir() / "ul"));
  // other subcommands than run
  const Result study = run_ranks(box, 2, {"calibrate", "--help-not-an-option"});
  EXPECT_EQ(study.status, 2);
  EXPECT_EQ(cosim_lines(study.err).size(), 1u) << study.err;
}
