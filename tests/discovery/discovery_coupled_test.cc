// Hidden effects found in the coupled simulator: `cosim diagnose` with coupled runs (the case
// reader of `cosim diagnose`, app::case_reader) on synthetic data with one effect hidden
// (generator.h, the ranges of draws.h). Diagnose names the effect, writes the extended
// case and runs the coupled simulator with the baseline and with the extended case on specimens
// held out of the extended fit; the simulator's held-out gain (baseline error / extended error,
// each the RMS over the simulated specimens of a specimen's error: the RMS of its peak residual
// and its curve's RMS residual, both over the data's noise) must be at least five, the
// acceptance number of a named effect.
// Spacing 5 mm (10 particles across a 50 mm core). The rock model's strength has no length
// scale, so 5 mm moves a peak by the discretisation only (measured: M1's UCS 282.8 MPa at 5 mm
// against 282.9 at 2.5 mm; the basalt diagnosis's extended CTCS at 10 MPa 278.4 against 278.3),
// far below the effects hidden here. Two specimens per data set (the two the baseline misses
// most) on one thread keep each test at 1-25 s. One seed per effect (seed 1, fixed in advance);
// COSIM_DISCOVERY_SEEDS runs others.
// End friction is simulated on a heterogeneous crack-band rock (Weibull m 10 on 5 mm cells; a
// homogeneous cylinder held at its ends fails at its rims first and is weakened by friction:
// README, Known limitations), the mean of three rocks, scaled to the extended model's standard
// specimen; the generator's friction-held ends also stiffen the curves (held_ends.h).
// Measured gains on seed 1 (two specimens each): tension cut-off 21.4, envelope curvature 46.1,
// machine compliance 21.1, crack closure 51.7, loading rate 11.7, size (heterogeneity) 14.9, end
// friction 6.40 (the short specimen: peak 129.4 MPa measured, baseline 110.3, extended 127.4).
#include "draws.h"
#include "generator.h"

#include <app/diagnose_command.h>
#include <coupling/case_parameters.h>
#include <diagnose/diagnose.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <memory>
#include <random>
#include <sstream>

namespace
{
  using namespace diagnose;

  using discovery::base;

  /// The seed, fixed in advance: 1 (COSIM_DISCOVERY_SEEDS runs others).
  std::vector<unsigned> seeds() { return discovery::seeds({1}); }

  /// The effect hidden in `t` at seed `seed`, in the ranges of draws.h ("none": none).
  void hide(discovery::Truth &t, const std::string &effect, unsigned seed)
  {
    if (effect == "none")
      return;
    discovery::draw(t, effect, seed); // before t.effects: the cut-off is the plain rock's fraction
    t.effects = {effect};
  }

  /// Diagnoses a data set with `effect` hidden, with coupled runs; prints a "[ result ]" line.
  /// `alter` (if any) changes each case the simulator runs after it is read.
  Diagnosis run(const std::string &effect, unsigned seed, double spacing,
                const std::function<void(const std::vector<std::string> &,
                                         coupling::CaseParameters &)> &alter = {})
  {
    auto t = base(seed);
    hide(t, effect, seed);
    // a neutral folder name: nothing about the hidden effect in any path diagnose sees
    const std::string dir = std::string(COSIM_BINARY_DIR) + "/discovery-data/coupled-" +
                            std::to_string(std::hash<std::string>{}(effect + std::to_string(seed)));
    discovery::write_folder(t, dir, seed, true);
    const std::string defaults = dir + "-defaults.prm";
    // every key at its default but the threads: one (ctest runs two tests side by side on two
    // cores; two threads each would oversubscribe them)
    std::ofstream(defaults) << "subsection SPH\n  set Threads = 1\nend\n";
    Options o;
    o.coupled_spacing = spacing;
    o.max_simulations = 2;
    o.read_case       = app::case_reader(defaults);
    if (alter)
      o.read_case = [plain = o.read_case, alter](const std::vector<std::string> &overrides,
                                                 coupling::CaseParameters &c, std::string &text) {
        plain(overrides, c, text);
        alter(overrides, c);
      };
    const Diagnosis d = diagnose::diagnose(read_data(dir), o);
    std::ostringstream line;
    line << "[ result ] coupled " << effect << " seed " << seed << ": identified";
    for (const auto &e : d.identified)
      line << ' ' << e;
    line << "; coupled held-out gain " << d.coupled_gain << " over " << d.simulations.size()
         << " specimens:";
    for (const auto &m : d.simulations)
      line << ' ' << m.name << " (" << m.test << ", peak " << m.measured_peak_MPa << " MPa, baseline "
           << m.baseline.peak_MPa << ", extended " << m.extended.peak_MPa << "; error "
           << m.baseline.error << " -> " << m.extended.error << ")";
    for (const auto &note : d.notes) // the fitted rock of a named end friction
      if (note.rfind("coupled simulator: end friction", 0) == 0)
        line << "\n[ result ]   " << note;
    std::cout << line.str() << '\n';
    return d;
  }

  void expect_gain(const std::string &effect, double spacing = 0.005)
  {
    for (unsigned seed : seeds())
    {
      const Diagnosis d = run(effect, seed, spacing);
      ASSERT_TRUE(std::find(d.identified.begin(), d.identified.end(), effect) != d.identified.end())
        << "seed " << seed << ": " << d.identified.front();
      ASSERT_FALSE(d.simulations.empty()) << "seed " << seed;
      for (const auto &m : d.simulations)
      {
        // every run failed its specimen past the peak or ran to its end strain (no instability)
        for (const auto *r : {&m.baseline, &m.extended})
        {
          EXPECT_TRUE(r->stop_reason == "post-peak drop" || r->stop_reason == "end strain")
            << m.name << ": " << r->stop_reason;
          EXPECT_GT(r->peak_MPa, 0) << m.name;
        }
      }
      // five: the acceptance number of a named effect's gain
      EXPECT_GE(d.coupled_gain, 5.0) << "seed " << seed;
    }
  }
} // namespace

// Clean data: nothing is named, so nothing is extended: the simulator runs (if the baseline
// misses a specimen by chance) give the same case twice and claim no gain.
TEST(DiscoveryCoupled, CleanDataClaimsNoGain)
{
  for (unsigned seed : seeds())
  {
    const Diagnosis d = run("none", seed, 0.005);
    EXPECT_EQ(d.identified, std::vector<std::string>{"none"}) << "seed " << seed;
    EXPECT_EQ(d.coupled_gain, 1.0) << "seed " << seed;
    for (const auto &m : d.simulations)
      EXPECT_EQ(m.baseline.peak_MPa, m.extended.peak_MPa) << m.name;
  }
}

// A Brazilian disc's displacement at its peak (a peak-only BTS curve: one row) is judged by the
// simulator alone (the surrogate has no disc displacement): the disc is run whatever the
// surrogate says, and the miss of its displacement is the simulated disc's own. Written once
// with three times the simulated displacement (the miss is two thirds of it) and once with the
// simulated one (no miss).
TEST(DiscoveryCoupled, BtsDisplacementAtPeakIsJudgedByTheSimulator)
{
  auto t = base(1);
  const std::string dir = std::string(COSIM_BINARY_DIR) + "/discovery-data/coupled-bts-displacement";
  discovery::write_folder(t, dir, 1, true);
  const double bts = discovery::true_tensile(t);
  const auto write_disc = [&](const double displacement_mm) {
    std::ofstream f(dir + "/curves/zz_disc.csv");
    f << "# test: BTS\n# group: A\n# diameter_mm: 50\n# thickness_mm: 25\n# displacement: platen\n"
      << "time_s,displacement_mm,force_kN\n0," << displacement_mm << ','
      << bts * 3.14159265358979 * 50 * 25 / 2 / 1e3 << '\n';
  };
  const std::string defaults = dir + "-defaults.prm";
  std::ofstream(defaults) << "subsection SPH\n  set Threads = 1\nend\n";
  const auto disc_of = [&](const double displacement_mm) {
    write_disc(displacement_mm);
    Options o;
    o.coupled_spacing = 0.005;
    o.max_simulations = 3;
    o.read_case       = app::case_reader(defaults);
    const Diagnosis d = diagnose::diagnose(read_data(dir), o);
    for (const auto &m : d.simulations)
      if (m.test == "BTS" && m.name.find("zz_disc") != std::string::npos)
        return m;
    ADD_FAILURE() << "the disc was not simulated";
    return Simulation{};
  };
  // the simulated disc's displacement at its peak, read from a first diagnosis
  const Simulation first = disc_of(1.0);
  ASSERT_EQ(first.n_points, 1);
  const double simulated = 1.0 - first.baseline.curve_rms_mm; // the simulation falls short of 1 mm
  std::printf("disc: simulated displacement at peak %.4f mm\n", simulated);
  ASSERT_GT(simulated, 0.005);
  ASSERT_LT(simulated, 0.1);
  // three times it: the miss is two thirds of the measured value. The generator's BTS load (Eq.
  // 15) lies above the simulated disc's peak, so the displacement is read at that peak both
  // times; measured 0.08804 mm = 2 x 0.04402 and 0 at 1x. 1 % and 0.5 % leave room for a
  // measured load below the peak, read on the rising curve.
  const Simulation far = disc_of(3 * simulated);
  EXPECT_NEAR(far.baseline.curve_rms_mm, 2 * simulated, 0.01 * simulated);
  // the simulated value itself: no miss
  const Simulation same = disc_of(simulated);
  EXPECT_LT(same.baseline.curve_rms_mm, 0.005 * simulated);
  std::printf("disc: miss %.5f mm at 3x, %.6f mm at 1x\n", far.baseline.curve_rms_mm,
              same.baseline.curve_rms_mm);
}

// Where the extended case does worse than the baseline in the simulator, the report says so and
// names the specimen: the extended cases of an end-friction diagnosis (those with platen
// friction) are run with a rock 20 % softer than they state, so that their curves miss by far
// more than the data's 0.2 % noise while the baselines are untouched.
TEST(DiscoveryCoupled, SaysWhereTheSimulatorDoesWorseThanTheBaseline)
{
  const Diagnosis d = run("end_friction", 1, 0.005,
                          [](const std::vector<std::string> &overrides, coupling::CaseParameters &c) {
                            for (const auto &line : overrides)
                              if (line.rfind("Platens/Friction coefficient=", 0) == 0)
                                c.rock.youngs_modulus *= 0.8;
                          });
  std::string notes;
  for (const auto &n : d.notes)
    notes += n + "\n";
  int worse_ones = 0;
  for (std::size_t i = 0; i < d.simulations.size(); ++i)
  {
    const Simulation &m = d.simulations[i];
    const bool worse    = m.extended.error > 1.05 * m.baseline.error + 0.5; // the rule's margin
    const std::string s = simulation_stem(i) + " (" + m.name;
    EXPECT_EQ(worse, notes.find(s) != std::string::npos) << s << "\n" << notes;
    worse_ones += worse;
  }
  EXPECT_GE(worse_ones, 1) << notes; // the softened rock does worse somewhere
  EXPECT_NE(notes.find("worse than the baseline"), std::string::npos) << notes;
}

// A coupled run that goes unstable does not end the diagnosis: its specimen is reported with
// where it went unstable and left out of the gain, which the other specimens give. The extended
// case (with a tensile strength) of the first specimen of a tension cut-off diagnosis runs at
// TSSFAC 5, five times the stable step (caught within a step: reliability_test); every other
// case runs as it is.
TEST(DiscoveryCoupled, AnUnstableRunIsReportedAndLeftOutOfTheGain)
{
  auto first = std::make_shared<std::string>(); // the first extended case's specimen
  const Diagnosis d = run("tension_cutoff", 1, 0.005,
                          [first](const std::vector<std::string> &overrides, coupling::CaseParameters &c) {
                            std::string specimen;
                            bool extended = false;
                            for (const auto &line : overrides)
                            {
                              if (line.rfind("Test/", 0) == 0)
                                specimen += line + "\n";
                              extended = extended || line.rfind("Rock/Tensile strength=", 0) == 0;
                            }
                            if (extended && first->empty())
                              *first = specimen;
                            if (extended && specimen == *first)
                              c.sph.tssfac = 5;
                          });
  ASSERT_EQ(d.simulations.size(), 2u) << "two specimens: one unstable, one to give the gain";
  std::string notes;
  for (const auto &n : d.notes)
    notes += n + "\n";
  const Simulation &bad = d.simulations[0], &good = d.simulations[1];
  EXPECT_FALSE(bad.baseline.unstable) << bad.baseline.stop_reason;
  ASSERT_TRUE(bad.extended.unstable) << bad.extended.stop_reason;
  EXPECT_EQ(bad.extended.stop_reason.rfind("unstable: step ", 0), 0u) << bad.extended.stop_reason;
  EXPECT_NE(notes.find(simulation_stem(0) + " (" + bad.name + ", " + bad.test + ") extended: unstable"),
            std::string::npos)
    << notes;
  EXPECT_FALSE(good.baseline.unstable || good.extended.unstable) << good.extended.stop_reason;
  EXPECT_EQ(coupled_unstable(d), 1);
  // the gain is the completed specimen's alone (the RMS over one specimen is its error)
  EXPECT_NEAR(d.coupled_gain, good.baseline.error / good.extended.error, 1e-12 * d.coupled_gain);
  EXPECT_NE(diagnosis_json(d).find("\"coupled_unstable\": 1"), std::string::npos);
}

// A run of a heterogeneous rock's fit (end friction) that goes unstable stops that fit, not the
// diagnosis: the specimens it serves are reported, each with the unstable run's case file.
TEST(DiscoveryCoupled, AnUnstableFitIsReportedWithTheCaseThatWentUnstable)
{
  const Diagnosis d = run("end_friction", 1, 0.005,
                          [](const std::vector<std::string> &overrides, coupling::CaseParameters &c) {
                            for (const auto &line : overrides)
                              if (line.rfind("Rock/Strength scatter=", 0) == 0)
                                c.sph.tssfac = 5;
                          });
  ASSERT_FALSE(d.simulations.empty());
  EXPECT_EQ(coupled_unstable(d), static_cast<int>(d.simulations.size()));
  EXPECT_TRUE(std::isnan(d.coupled_gain)) << d.coupled_gain;
  for (const auto &m : d.simulations)
  {
    EXPECT_FALSE(m.baseline.unstable) << m.name << ": " << m.baseline.stop_reason;
    EXPECT_TRUE(m.extended.unstable) << m.name;
    EXPECT_EQ(m.extended.stop_reason.rfind("not run: the fit of its rock stopped, at E G_I", 0), 0u)
      << m.extended.stop_reason;
    // every rock goes unstable at TSSFAC 5: the first one is named, with its step
    EXPECT_NE(m.extended.stop_reason.find("specimen's rock 1 unstable: step "), std::string::npos)
      << m.extended.stop_reason;
    // the first rock went unstable: its case file is the one given
    const std::size_t at = m.extended.case_text.find("set Scatter seed ");
    ASSERT_NE(at, std::string::npos) << m.extended.case_text;
    const std::string line = m.extended.case_text.substr(at, m.extended.case_text.find('\n', at) - at);
    EXPECT_NE(line.find("= 1"), std::string::npos) << line;
  }
}

TEST(DiscoveryCoupled, TensionCutoff) { expect_gain("tension_cutoff"); }
TEST(DiscoveryCoupled, EnvelopeCurvature) { expect_gain("envelope_curvature"); }
TEST(DiscoveryCoupled, MachineCompliance) { expect_gain("machine_compliance"); }
TEST(DiscoveryCoupled, CrackClosure) { expect_gain("crack_closure"); }
TEST(DiscoveryCoupled, LoadingRate) { expect_gain("loading_rate"); }
TEST(DiscoveryCoupled, EndFriction) { expect_gain("end_friction"); }

// Seed 4's data (mu 0.33 by Siebel's law) give the short specimen a smaller share of strength
// than this rock gives at any brittleness the 5 mm crack band admits (l = 0.55 of the band,
// 5.5 mm: the ratio 4.7 % above the model's); the fit then lowers the simulator's own friction
// coefficient at that l until the ratio is the model's. Measured: mu 0.272 and 0.271 for the
// model's 0.335 and 0.330, gain 8.61 (4.93 with the model's mu held); 60 s.
TEST(DiscoveryCoupled, EndFrictionStrongerThanTheMostBrittleRockLowersTheSimulatorsMu)
{
  const Diagnosis d = run("end_friction", 4, 0.005);
  ASSERT_TRUE(std::find(d.identified.begin(), d.identified.end(), "end_friction") != d.identified.end());
  int lowered = 0;
  for (const auto &note : d.notes)
    if (note.rfind("coupled simulator: end friction", 0) == 0)
    {
      // "end friction mu <model> (the simulator's <fitted>: ...": the fitted one lower, not zero
      const auto at = note.find("(the simulator's ");
      ASSERT_NE(at, std::string::npos) << note;
      const double model  = std::stod(note.substr(note.find(" mu ") + 4));
      const double fitted = std::stod(note.substr(at + 17));
      EXPECT_LT(fitted, model) << note;
      EXPECT_GT(fitted, 0.5 * model) << note; // measured 0.81 of it: friction still holds
      ++lowered;
    }
  EXPECT_GE(lowered, 1);
  EXPECT_GE(d.coupled_gain, 5.0); // five: the acceptance number of a named effect's gain
}
// the size study's 100 and 150 mm cores at 10 mm, 10 and 15 particles across (at 5 mm they are
// 20 across, 12,600 particles each, and the test takes three minutes)
TEST(DiscoveryCoupled, Heterogeneity) { expect_gain("heterogeneity", 0.01); }
