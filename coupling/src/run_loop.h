#pragma once
/// @file
/// The run loop every coupled test shares (UCS, BTS, CTCS, indentation, linear cutting): step,
/// stability check, history rows, snapshots, progress, checkpoints and stop requests. A driver
/// builds its bodies and says how to take one step and what to measure (SteppedTest); RunLoop
/// does the rest, the same way for every test type. Internal to the coupling library.
///
/// Lifecycle of RunLoop::run:
///   1. with a resume state: the driver's load_state and the loop's own arrays, then the history
///      rows so far reported again; without: a snapshot of the start if the schedule asks;
///   2. the current state is checked and kept as the last good one;
///   3. per step: SteppedTest::step, the stability check (on failure RunObserver::last_good_state,
///      then InstabilityError), a history row when due (SteppedTest::measure, then
///      SteppedTest::stop_reason), a snapshot when due or at the end, progress every 20 steps, and
///      a checkpoint when due (or a final one and RunInterrupted on a stop request);
///   4. ends at RunSchedule::end_time or when stop_reason gives a reason.

#include <coupling/case_parameters.h>
#include <coupling/run_output.h>

#include <cstddef>
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace sph
{
  template <int dim>
  class Body;
  class Domain;
}
namespace fem
{
  class SteelBody;
}

namespace coupling
{
  /// One history row and, at the same instant, the rock's own energies for the quasi-static check.
  struct Measurement
  {
    HistoryRow row;
    double rock_kinetic  = 0; ///< the rock's kinetic energy the test counts as dynamic [J]
    double rock_internal = 0; ///< the rock's elastic strain energy [J]
  };

  /// What a driver gives the run loop: the narrow interface of a coupled test.
  class SteppedTest
  {
  public:
    virtual ~SteppedTest() = default;
    /// One coupled step (SPH, contact, FEM sub-steps); advances time() and n_steps().
    virtual void step()                 = 0;
    virtual double time() const         = 0; ///< [s]
    virtual std::size_t n_steps() const = 0;
    /// Work done on the rock so far (frame, confinement) [J]: bounds the kinetic energy of a stable
    /// run.
    virtual double external_work() const = 0;
    /// A history row now (may reset what the driver integrates between rows).
    virtual Measurement measure() = 0;
    /// Called after each recorded row: the driver's own account of the run (peak, failure
    /// pattern), and the stop criterion: a reason to stop now ("post-peak drop"), or "" to go on.
    virtual std::string stop_reason(const HistoryRow &row)   = 0;
    virtual ParticleSnapshot particle_snapshot() const       = 0;
    virtual std::vector<MeshSnapshot> mesh_snapshots() const = 0;
    /// The driver's part of a checkpoint (bodies, contacts, its clocks and accounts); the loop
    /// adds its own (history rows, row and snapshot clocks) under "loop.".
    virtual void save_state(StateArrays &out) const = 0;
    /// Restores save_state's arrays; InputError when they belong to another case.
    virtual void load_state(const StateArrays &in) = 0;
    /// A distributed run: which arrays of the last save_state are this rank's rows of a
    /// whole-body array; nullptr (the default): all are whole.
    virtual const StateRows *state_rows() const { return nullptr; }
  };

  /// When rows and snapshots are taken and when the run ends, all in simulated time [s].
  struct RunSchedule
  {
    double end_time          = 0;     ///< the run ends at the first step at or past it [s]
    double progress_time     = 0;     ///< time that counts as the whole run for progress [s]
    double row_interval      = 0;     ///< [s]
    double snapshot_interval = 0;     ///< [s]
    double first_row         = 0;     ///< time of the first history row [s]
    double first_snapshot    = 0;     ///< time of the first snapshot after the start [s]
    bool snapshot_at_start   = false; ///< also a snapshot of the state before the first step
    std::string end_reason;           ///< the stop reason when end_time is reached
  };

  /// What the stability check watches and its bounds.
  struct StabilityWatch
  {
    const sph::Body<3> *rock = nullptr;
    /// A distributed rock: this rank's part (the checks then scan the owned particles and
    /// agree over the ranks); null on one rank.
    const sph::Domain *domain = nullptr;
    /// The steel bodies, each with its name in messages ("top platen", "cutter").
    std::vector<std::pair<std::string, const fem::SteelBody *>> steel;
    double domain_size  = 0; ///< a particle with |x_d| >= this has left the domain [m]
    double energy_floor = 0; ///< kinetic-energy allowance at the start [J]
    double time_step    = 0; ///< the coupled step in use [s]
    double tssfac       = 1; ///< SPH/TSSFAC as given (also above 1) [-]
    /// What to suggest when the run goes unstable, e.g. "a time step above the stable limit ...".
    std::string likely_cause;
  };

  class RunLoop
  {
  public:
    RunLoop(SteppedTest &test, const RunSchedule &schedule, StabilityWatch watch,
            const OutputParameters &output);
    /// Runs to the end of the schedule or the driver's stop criterion; returns the stop reason.
    /// Throws InstabilityError (after RunObserver::last_good_state), RunInterrupted (after a final
    /// checkpoint), InputError for a resume state of another case.
    std::string run(RunObserver &observer, const StateArrays *resume = nullptr);

    /// The rows recorded (after a resume: with those of the interrupted run).
    const std::vector<HistoryRow> &rows() const { return rows_; }
    /// Per row: Measurement::rock_kinetic and rock_internal [J].
    const std::vector<double> &rock_kinetic() const { return rock_kinetic_; }
    const std::vector<double> &rock_internal() const { return rock_internal_; }

  private:
    void save_state(StateArrays &out) const;
    void load_state(const StateArrays &in);
    /// Non-finite positions, velocities, stress or smoothing lengths, particles out of the
    /// domain, kinetic energy above ten times the work done plus the floor, a stable step below
    /// half the one in use, non-finite steel bodies. On failure reports the last good state and
    /// throws InstabilityError; otherwise keeps the current state as the last good one.
    void check_stability(RunObserver &observer);
    /// Reports the last good state to `observer` and throws InstabilityError with `what`, where
    /// (particle `i`, or none for i < 0) and `cause`.
    [[noreturn]] void fail(RunObserver &observer, const std::string &what, long i,
                           const std::string &cause) const;
    void keep_last_good();

    SteppedTest &test_;
    RunSchedule schedule_;
    StabilityWatch watch_;
    OutputParameters output_;
    std::vector<HistoryRow> rows_;
    std::vector<double> rock_kinetic_, rock_internal_;
    double next_row_ = 0, next_snap_ = 0; ///< times of the next history row and snapshot [s]
    ParticleSnapshot last_good_;
    std::size_t last_good_step_ = 0;
    // distributed runs: the stop and time-checkpoint wishes of all ranks, agreed by
    // check_stability's one collective of the step (the same on every rank)
    std::chrono::steady_clock::time_point last_checkpoint_ = std::chrono::steady_clock::now();
    bool agreed_stop_ = false, agreed_by_time_ = false;
    double last_good_time_      = 0;
  };
} // namespace coupling
