// RunLoop on its own, driven by a stand-in test (a tiny SPH block that only the stand-in moves):
// when rows and snapshots come, what ends the run, checkpoint and resume, and the stability check
// handing over the last good state. The drivers' own physics is tested elsewhere; here nothing
// but the loop can make these tests fail.
#include "../../coupling/src/run_loop.h"

#include <coupling/errors.h>

#include <sph/body.h>
#include <sph/lattice.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <memory>
#include <string>
#include <vector>

using namespace coupling;

namespace
{
  /// 27 particles of elastic rock, 1 mm apart, at rest.
  std::unique_ptr<sph::Body<3>> tiny_block()
  {
    sph::Parameters p;
    p.spacing = 1e-3;
    sph::MaterialParameters m;
    m.model = sph::RockModel::elastic;
    const sph::Lattice<3> lat =
      sph::make_block<3>(sph::Vector<3>::Zero(), sph::Vector<3>::Constant(3e-3), 1e-3);
    return std::make_unique<sph::Body<3>>(p, m, lat.positions, lat.volumes);
  }

  // steps of 1/64 s and rows every 1/8 s: every time below is exact in binary
  constexpr double dt = 1.0 / 64;

  /// Counts steps (the block stays at rest unless kicked); measures the step count as the force.
  class Ticker : public SteppedTest
  {
  public:
    explicit Ticker(sph::Body<3> &body)
        : body_(body)
    {}
    std::size_t kick_from  = 0; ///< from this step on, a huge force on particle 0 (0: never)
    std::size_t nan_row_at = 0; ///< the row at this step has a NaN force (0: never)
    std::size_t stop_row   = 0; ///< stop_reason says "enough" at this row (0: never)

    void step() override
    {
      // the block itself is not integrated at the loop's step (far above its stable one)
      if (kick_from > 0 && n_ + 1 >= kick_from)
      {
        body_.compute_forces();
        body_.external_forces()[0][2] += 1e9;
        body_.integrate(1e-6);
      }
      t_ += dt;
      ++n_;
    }
    double time() const override { return t_; }
    std::size_t n_steps() const override { return n_; }
    double external_work() const override { return 0; }
    Measurement measure() override
    {
      Measurement m;
      m.row.time  = t_;
      m.row.force = n_ == nan_row_at ? std::numeric_limits<double>::quiet_NaN() : double(n_);
      return m;
    }
    std::string stop_reason(const HistoryRow &) override
    {
      return ++n_rows_ == stop_row ? "enough" : "";
    }
    ParticleSnapshot particle_snapshot() const override
    {
      ParticleSnapshot s;
      s.n = body_.n_particles();
      return s;
    }
    std::vector<MeshSnapshot> mesh_snapshots() const override { return {}; }
    void save_state(StateArrays &out) const override
    {
      body_.save_state(out, "body.");
      out["ticker"] = {t_, double(n_), double(n_rows_)};
    }
    void load_state(const StateArrays &in) override
    {
      body_.load_state(in, "body.");
      const auto &d = in.at("ticker");
      t_            = d[0];
      n_            = static_cast<std::size_t>(d[1]);
      n_rows_       = static_cast<std::size_t>(d[2]);
    }

  private:
    sph::Body<3> &body_;
    double t_           = 0;
    std::size_t n_      = 0;
    std::size_t n_rows_ = 0;
  };

  struct Log : RunObserver
  {
    std::vector<HistoryRow> rows;
    std::vector<double> snapshot_times, fractions;
    StateArrays checkpoint_state;
    std::size_t checkpoint_step = 0, n_checkpoints = 0;
    long good_step             = -1;
    std::size_t good_particles = 0;
    void history(const HistoryRow &r) override { rows.push_back(r); }
    void snapshot(double t, const ParticleSnapshot &, const std::vector<MeshSnapshot> &) override
    {
      snapshot_times.push_back(t);
    }
    void progress(std::size_t, double, double fraction) override { fractions.push_back(fraction); }
    void checkpoint(std::size_t step, const StateArrays &state, const StateRows *) override
    {
      checkpoint_state = state;
      checkpoint_step  = step;
      ++n_checkpoints;
    }
    void last_good_state(std::size_t step, double, const ParticleSnapshot &p) override
    {
      good_step      = static_cast<long>(step);
      good_particles = p.n;
    }
  };

  RunSchedule one_second()
  {
    RunSchedule s;
    s.end_time          = 1.0;
    s.progress_time     = 1.0;
    s.row_interval      = 0.125;
    s.first_row         = 0.125;
    s.snapshot_interval = 0.25;
    s.first_snapshot    = 0.25;
    s.snapshot_at_start = true;
    s.end_reason        = "end of path";
    return s;
  }

  StabilityWatch watch(const sph::Body<3> &body)
  {
    StabilityWatch w;
    w.rock         = &body;
    w.domain_size  = 0.02;
    w.energy_floor = 1e300; // the kick is to leave the domain, not to trip the energy bound
    w.time_step    = 0;     // ... nor the time-step bound
    w.likely_cause = "a kick";
    return w;
  }
} // namespace

TEST(RunLoop, RowsSnapshotsAndProgressFollowTheSchedule)
{
  const auto body_owner = tiny_block();
  sph::Body<3> &body    = *body_owner;
  Ticker test(body);
  RunLoop loop(test, one_second(), watch(body), OutputParameters());
  Log log;
  EXPECT_EQ(loop.run(log), "end of path");
  // 64 steps; a row every 8 steps, the last one at the end
  ASSERT_EQ(log.rows.size(), 8u);
  for (std::size_t k = 0; k < 8; ++k)
    EXPECT_EQ(log.rows[k].force, 8.0 * (k + 1)) << "row " << k; // step counts: exact
  EXPECT_EQ(loop.rows().size(), 8u);
  EXPECT_EQ(loop.rock_kinetic().size(), 8u);
  // the start, then every quarter second
  EXPECT_EQ(log.snapshot_times, (std::vector<double>{0, 0.25, 0.5, 0.75, 1.0}));
  // every 20 steps and at the end
  EXPECT_EQ(log.fractions, (std::vector<double>{20 * dt, 40 * dt, 60 * dt, 1.0}));
}

TEST(RunLoop, TheDriversStopReasonEndsTheRunAtThatRow)
{
  const auto body_owner = tiny_block();
  sph::Body<3> &body    = *body_owner;
  Ticker test(body);
  test.stop_row = 3;
  RunLoop loop(test, one_second(), watch(body), OutputParameters());
  Log log;
  EXPECT_EQ(loop.run(log), "enough");
  EXPECT_EQ(log.rows.size(), 3u);
  EXPECT_EQ(test.n_steps(), 24u);
  // a snapshot of the final state
  EXPECT_EQ(log.snapshot_times.back(), 24 * dt);
}

TEST(RunLoop, StopAfterStepsCheckpointsAndTheCheckpointContinuesTheRun)
{
  const auto body_owner = tiny_block();
  sph::Body<3> &body    = *body_owner;
  Ticker whole_test(body);
  RunLoop whole(whole_test, one_second(), watch(body), OutputParameters());
  Log all;
  whole.run(all);

  const auto body1_owner = tiny_block();
  sph::Body<3> &body1    = *body1_owner;
  Ticker first_test(body1);
  OutputParameters stop;
  stop.stop_after_steps = 20;
  RunLoop first(first_test, one_second(), watch(body1), stop);
  Log part;
  EXPECT_THROW(first.run(part), RunInterrupted);
  EXPECT_EQ(part.n_checkpoints, 1u);
  EXPECT_EQ(part.checkpoint_step, 20u);
  EXPECT_EQ(part.rows.size(), 2u);

  const auto body2_owner = tiny_block();
  sph::Body<3> &body2    = *body2_owner;
  Ticker second_test(body2);
  RunLoop second(second_test, one_second(), watch(body2), OutputParameters());
  Log rest;
  EXPECT_EQ(second.run(rest, &part.checkpoint_state), "end of path");
  // the rows so far are reported again, then the run goes on as if never stopped
  ASSERT_EQ(rest.rows.size(), all.rows.size());
  for (std::size_t k = 0; k < all.rows.size(); ++k)
  {
    EXPECT_EQ(rest.rows[k].time, all.rows[k].time) << "row " << k;
    EXPECT_EQ(rest.rows[k].force, all.rows[k].force) << "row " << k;
  }
  // no snapshot of the start again, and the next snapshot where the interrupted run left it
  EXPECT_EQ(rest.snapshot_times, (std::vector<double>{0.5, 0.75, 1.0}));
}

TEST(RunLoop, ACheckpointWithoutTheLoopsArraysIsAnInputError)
{
  const auto body_owner = tiny_block();
  sph::Body<3> &body    = *body_owner;
  Ticker test(body);
  StateArrays state;
  test.save_state(state); // the driver's part only
  RunLoop loop(test, one_second(), watch(body), OutputParameters());
  Log log;
  EXPECT_THROW(loop.run(log, &state), InputError);
}

TEST(RunLoop, AParticleLeavingTheDomainIsCaughtWithTheStateOfTheStepBefore)
{
  const auto body_owner = tiny_block();
  sph::Body<3> &body    = *body_owner;
  Ticker test(body);
  test.kick_from = 5;
  RunLoop loop(test, one_second(), watch(body), OutputParameters());
  Log log;
  try
  {
    loop.run(log);
    FAIL() << "a particle kicked with 1e9 N stayed in a 2 cm domain";
  }
  catch (const InstabilityError &e)
  {
    const std::string what = e.what();
    ASSERT_GE(log.good_step, 4) << "no last good state reported, or one before the kick";
    EXPECT_EQ(log.good_particles, body.n_particles());
    EXPECT_EQ(what.rfind("step " + std::to_string(log.good_step + 1) + ",", 0), 0u) << what;
    for (const char *part : {"at particle 0 ", "likely cause: a kick", "last good state: step"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " missing in: " << what;
  }
}

TEST(RunLoop, ANonFiniteHistoryRowIsAnInstability)
{
  const auto body_owner = tiny_block();
  sph::Body<3> &body    = *body_owner;
  Ticker test(body);
  test.nan_row_at = 16;
  RunLoop loop(test, one_second(), watch(body), OutputParameters());
  Log log;
  EXPECT_THROW(loop.run(log), InstabilityError);
  EXPECT_EQ(log.rows.size(), 1u);
  EXPECT_EQ(log.good_step, 16); // the particles passed at that step; the row did not
}
