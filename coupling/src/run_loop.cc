#include "run_loop.h"

#include "driver_common.h"

#include <coupling/errors.h>

#include <fem/steel_body.h>
#include <sph/body.h>
#include <sph/domain.h>

#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>

namespace coupling
{
  namespace
  {
    /// Every HistoryRow field in a checkpoint, in declaration order.
    constexpr std::size_t history_width = 15;

    /// After step n_steps: a checkpoint (save_state, then observer.checkpoint) every
    /// Output/Checkpoint interval steps and/or minutes since last_checkpoint (updated), and a
    /// final one with RunInterrupted thrown when the observer asks to stop or Output/Stop after
    /// steps is reached.
    template <typename SaveState>
    void checkpoint_or_stop(RunObserver &observer, const OutputParameters &output,
                            const std::size_t n_steps, const double time,
                            std::chrono::steady_clock::time_point &last_checkpoint,
                            const SaveState &save_state, const StateRows *rows,
                            const bool *agreed)
    {
      const auto now = std::chrono::steady_clock::now();
      bool stop_asked =
        observer.stop_requested() || (output.stop_after_steps > 0 &&
                                      n_steps == static_cast<std::size_t>(output.stop_after_steps));
      const bool by_steps = output.checkpoint_steps > 0 &&
                            n_steps % static_cast<std::size_t>(output.checkpoint_steps) == 0;
      bool by_time = output.checkpoint_minutes > 0 &&
                     std::chrono::duration<double>(now - last_checkpoint).count() >=
                       60.0 * output.checkpoint_minutes;
      if (agreed) // distributed: what all ranks agreed (a signal or a clock of any rank)
      {
        stop_asked = agreed[0] || (output.stop_after_steps > 0 &&
                                   n_steps == static_cast<std::size_t>(output.stop_after_steps));
        by_time    = agreed[1];
      }
      if (stop_asked || by_steps || by_time)
      {
        StateArrays state;
        save_state(state);
        observer.checkpoint(n_steps, state, rows);
        last_checkpoint = now;
      }
      if (stop_asked)
      {
        std::ostringstream os;
        os << "stopped on request after step " << n_steps << ", t = " << time << " s";
        throw RunInterrupted(os.str());
      }
    }
  } // namespace

  RunLoop::RunLoop(SteppedTest &test, const RunSchedule &schedule, StabilityWatch watch,
                   const OutputParameters &output)
      : test_(test)
      , schedule_(schedule)
      , watch_(std::move(watch))
      , output_(output)
  {}

  std::string RunLoop::run(RunObserver &observer, const StateArrays *resume)
  {
    if (resume)
    {
      load_state(*resume);
      for (const auto &r : rows_)
        observer.history(r);
    }
    else
    {
      next_row_  = schedule_.first_row;
      next_snap_ = schedule_.first_snapshot;
      if (schedule_.snapshot_at_start)
        observer.snapshot(test_.time(), test_.particle_snapshot(), test_.mesh_snapshots());
    }
    check_stability(observer); // the start (or the restored state) is the first good state

    auto &last_checkpoint = last_checkpoint_;
    last_checkpoint       = std::chrono::steady_clock::now();
    std::string reason;
    while (true)
    {
      test_.step();
      check_stability(observer);
      const double t  = test_.time();
      const bool last = t >= schedule_.end_time;
      bool stop       = false;
      if (t >= next_row_ || last)
      {
        const Measurement m = test_.measure();
        const HistoryRow &r = m.row;
        if (!std::isfinite(r.force + r.kinetic_energy + r.internal_energy))
          fail(observer, "non-finite load-cell force or energy in the history row", -1,
               watch_.likely_cause);
        rows_.push_back(r);
        rock_kinetic_.push_back(m.rock_kinetic);
        rock_internal_.push_back(m.rock_internal);
        observer.history(r);
        next_row_ += schedule_.row_interval;
        reason = test_.stop_reason(r);
        stop   = !reason.empty();
        if (last)
        {
          stop = true;
          if (reason.empty())
            reason = schedule_.end_reason;
        }
      }
      if (t >= next_snap_ || stop)
      {
        observer.snapshot(t, test_.particle_snapshot(), test_.mesh_snapshots());
        next_snap_ += schedule_.snapshot_interval;
      }
      const std::size_t n = test_.n_steps();
      const bool agreed[2] = {agreed_stop_, agreed_by_time_};
      if (n % 20 == 0 || stop)
        observer.progress(n, t, std::min(1.0, t / schedule_.progress_time));
      if (stop)
        break;

      // checkpoints: every N steps and/or M minutes, and a final one when asked to stop
      checkpoint_or_stop(observer, output_, n, t, last_checkpoint,
                         [this](StateArrays &state) { save_state(state); }, test_.state_rows(),
                         watch_.domain ? agreed : nullptr);
    }
    return reason;
  }

  void RunLoop::save_state(StateArrays &out) const
  {
    test_.save_state(out);
    out["loop.clock"] = {next_row_, next_snap_};
    std::vector<double> history;
    history.reserve(history_width * rows_.size());
    for (const auto &r : rows_)
      append_history_row(history, r, history_width);
    out["loop.history"]       = std::move(history);
    out["loop.rock_kinetic"]  = rock_kinetic_;
    out["loop.rock_internal"] = rock_internal_;
  }

  void RunLoop::load_state(const StateArrays &in)
  {
    // the driver's first: it tells a checkpoint of another case
    test_.load_state(in);
    const auto c = in.find("loop.clock"), h = in.find("loop.history");
    const auto k = in.find("loop.rock_kinetic"), u = in.find("loop.rock_internal");
    if (c == in.end() || h == in.end() || k == in.end() || u == in.end())
      throw InputError("checkpoint: no loop.clock / loop.history / loop.rock_kinetic / "
                       "loop.rock_internal; a checkpoint of an older cosim? Restart it with the "
                       "version that wrote it");
    const std::size_t n_rows = h->second.size() / history_width;
    if (c->second.size() != 2 || h->second.size() % history_width != 0 ||
        k->second.size() != n_rows || u->second.size() != n_rows)
      throw InputError("checkpoint: loop arrays of the wrong size (a checkpoint of another "
                       "case?)");
    next_row_  = c->second[0];
    next_snap_ = c->second[1];
    rows_.clear();
    for (std::size_t r = 0; r < n_rows; ++r)
      rows_.push_back(history_row_at(h->second, r, history_width));
    rock_kinetic_  = k->second;
    rock_internal_ = u->second;
  }

  void RunLoop::fail(RunObserver &observer, const std::string &what, const long i,
                     const std::string &cause) const
  {
    std::ostringstream os;
    os << "step " << test_.n_steps() << ", t = " << test_.time() << " s: " << what;
    if (i >= 0)
    {
      const auto &x = watch_.rock->positions();
      os << " at particle " << i << " (" << x[i][0] << ", " << x[i][1] << ", " << x[i][2] << ") m";
    }
    os << "; likely cause: " << cause << "; last good state: step " << last_good_step_
       << ", t = " << last_good_time_ << " s";
    if (const sph::Domain *domain = watch_.domain) // (every rank fails at the same step)
    {
      ParticleSnapshot all;
      all.n            = domain->n_global();
      all.position     = domain->gather(last_good_.position.data(), 3);
      all.velocity     = domain->gather(last_good_.velocity.data(), 3);
      all.displacement = domain->gather(last_good_.displacement.data(), 3);
      all.stress       = domain->gather(last_good_.stress.data(), 6);
      all.plastic_strain = domain->gather(last_good_.plastic_strain.data(), 1);
      all.damage         = domain->gather(last_good_.damage.data(), 1);
      // the domain gathers doubles: the modes (small ints) go through them exactly
      const std::vector<double> modes(last_good_.failure_mode.begin(), last_good_.failure_mode.end());
      for (const double mode : domain->gather(modes.data(), 1))
        all.failure_mode.push_back(static_cast<int>(mode));
      observer.last_good_state(last_good_step_, last_good_time_, all);
      throw InstabilityError(os.str());
    }
    observer.last_good_state(last_good_step_, last_good_time_, last_good_);
    throw InstabilityError(os.str());
  }

  void RunLoop::check_stability(RunObserver &observer)
  {
    const sph::Body<3> &body     = *watch_.rock;
    const auto &x                = body.positions();
    const auto &v                = body.velocities();
    const auto &h                = body.smoothing_lengths();
    const auto &m                = body.masses();
    const double c               = body.wave_speed();
    const unsigned int n         = body.n_particles();
    const double domain          = watch_.domain_size;
    const std::string &too_large = watch_.likely_cause;
    // one pass over the particles, a contiguous chunk per thread; the chunks' results are
    // combined in chunk order, so the first bad particle, the fastest one and the one with the
    // smallest step are the lowest-index ones, as in a serial loop, and the kinetic energy is the
    // same for a given thread count
    struct Scan
    {
      long bad        = -1;   // first particle that is non-finite or out of the domain
      bool bad_finite = true; // ... and whether it was finite (then: out of the domain)
      double kinetic = 0, dt_min = 1e300, v_max = 0;
      unsigned int i_dt = 0, i_v = 0;
    };
    std::vector<Scan> scans(static_cast<std::size_t>(omp_get_max_threads()));
    // a distributed rock: the owned particles only (the outer ghosts' state is not computed)
    const sph::Domain *parts    = watch_.domain;
    const std::uint8_t *owned   = parts ? parts->owned().data() : nullptr;
#pragma omp parallel
    {
      const long t = omp_get_thread_num(), nt = omp_get_num_threads();
      Scan &r = scans[t];
      for (long i = n * t / nt; i < n * (t + 1) / nt; ++i)
      {
        if (owned && !owned[i])
          continue;
        const auto &s3 = body.stress3(i);
        const bool finite =
          std::isfinite(x[i][0] + x[i][1] + x[i][2] + v[i][0] + v[i][1] + v[i][2]) &&
          std::isfinite(s3.sum() + h[i]);
        if (!finite || !(std::abs(x[i][0]) < domain && std::abs(x[i][1]) < domain &&
                         std::abs(x[i][2]) < domain))
        {
          r.bad        = i;
          r.bad_finite = finite;
          break;
        }
        const double speed = v[i].norm();
        r.kinetic += 0.5 * m[i] * speed * speed;
        if (speed > r.v_max)
        {
          r.v_max = speed;
          r.i_v   = static_cast<unsigned int>(i);
        }
        const double dt_i = h[i] / (c + speed);
        if (dt_i < r.dt_min)
        {
          r.dt_min = dt_i;
          r.i_dt   = static_cast<unsigned int>(i);
        }
      }
    }
    double kinetic = 0, dt_min = 1e300, v_max = 0;
    unsigned int i_dt = 0, i_v = 0;
    for (const Scan &r : scans)
    {
      if (r.bad >= 0)
      {
        if (!r.bad_finite)
          fail(observer, "non-finite position, velocity, stress or smoothing length", r.bad,
               too_large);
        fail(observer, "a particle left the domain (|x| >= " + std::to_string(domain) + " m)",
             r.bad, too_large + ", or a loading body that lost contact");
      }
      kinetic += r.kinetic;
      if (r.v_max > v_max)
      {
        v_max = r.v_max;
        i_v   = r.i_v;
      }
      if (r.dt_min < dt_min)
      {
        dt_min = r.dt_min;
        i_dt   = r.i_dt;
      }
    }
    if (parts)
    {
      // every rank's scan; the first bad particle of the lowest rank, the kinetic energy summed
      // in rank order, the fastest particle and the smallest step over all ranks
      long bad = -1;
      bool bad_finite = true;
      for (const Scan &r : scans)
        if (r.bad >= 0)
        {
          bad        = r.bad;
          bad_finite = r.bad_finite;
          break;
        }
      const auto gid = [&](const long i) { return static_cast<double>(parts->global_ids()[i]); };
      // (with the wishes to stop or to checkpoint by the clock: one collective a step)
      const OutputParameters &output = output_;
      const bool by_time =
        output.checkpoint_minutes > 0 &&
        std::chrono::duration<double>(std::chrono::steady_clock::now() - last_checkpoint_).count() >=
          60.0 * output.checkpoint_minutes;
      std::vector<double> mine = {bad >= 0 ? gid(bad) : -1.0, bad_finite ? 1.0 : 0.0, 0, 0, 0,
                                  kinetic, dt_min, gid(i_dt), v[i_dt].norm(), h[i_dt], v_max,
                                  gid(i_v), 0, 0, 0, observer.stop_requested() ? 1.0 : 0.0,
                                  by_time ? 1.0 : 0.0};
      if (bad >= 0)
        for (int d = 0; d < 3; ++d)
          mine[2 + d] = x[bad][d];
      for (int d = 0; d < 3; ++d)
        mine[12 + d] = x[i_v][d];
      constexpr std::size_t w = 17;
      const std::vector<double> all = parts->all_gather(mine);
      agreed_stop_ = agreed_by_time_ = false;
      for (std::size_t k = 0; k < all.size(); k += w)
      {
        agreed_stop_    = agreed_stop_ || all[k + 15] != 0.0;
        agreed_by_time_ = agreed_by_time_ || all[k + 16] != 0.0;
      }
      kinetic = 0;
      dt_min  = 1e300;
      v_max   = 0;
      std::size_t at_dt = 0, at_v = 0, at_bad = all.size();
      for (std::size_t k = 0; k < all.size(); k += w)
      {
        if (all[k] >= 0 && at_bad == all.size())
          at_bad = k;
        kinetic += all[k + 5];
        if (all[k + 6] < dt_min)
          dt_min = all[k + 6], at_dt = k;
        if (all[k + 10] > v_max)
          v_max = all[k + 10], at_v = k;
      }
      auto where = [&](const std::size_t k, const int first) {
        std::ostringstream os;
        os << " at particle " << static_cast<long>(all[k]) << " (" << all[k + first] << ", "
           << all[k + first + 1] << ", " << all[k + first + 2] << ") m";
        return os.str();
      };
      if (at_bad < all.size())
      {
        if (all[at_bad + 1] == 0.0)
          fail(observer, "non-finite position, velocity, stress or smoothing length" + where(at_bad, 2),
               -1, too_large);
        fail(observer, "a particle left the domain (|x| >= " + std::to_string(domain) + " m)" +
                         where(at_bad, 2),
             -1, too_large + ", or a loading body that lost contact");
      }
      const double work = std::max(0.0, test_.external_work());
      if (kinetic > 10.0 * (work + watch_.energy_floor))
      {
        std::ostringstream os;
        os << "rock kinetic energy " << kinetic << " J above ten times the work done on it plus "
           << "the start-up allowance (" << work << " + " << watch_.energy_floor
           << " J), fastest particle |v| = " << v_max << " m/s";
        std::ostringstream at;
        at << " (particle " << static_cast<long>(all[at_v + 11]) << " at (" << all[at_v + 12] << ", "
           << all[at_v + 13] << ", " << all[at_v + 14] << ") m)";
        fail(observer, os.str() + at.str(), -1, too_large);
      }
      const double dt_stable = watch_.tssfac * dt_min;
      if (dt_stable < 0.5 * watch_.time_step)
      {
        std::ostringstream os;
        os << "collapsing time step: the stable step " << dt_stable << " s fell below half the step "
           << "in use " << watch_.time_step << " s (|v| = " << all[at_dt + 8]
           << " m/s, h = " << all[at_dt + 9] << " m, particle " << static_cast<long>(all[at_dt + 7])
           << ")";
        fail(observer, os.str(), -1, too_large);
      }
      i_dt = i_v = 0;
      dt_min = 1e300; // checked above
    }
    // a stable run never holds more kinetic energy than the work done on it (energy balance);
    // the floor covers the start, when that work is still tiny
    const double work = std::max(0.0, test_.external_work());
    if (!parts && kinetic > 10.0 * (work + watch_.energy_floor))
    {
      std::ostringstream os;
      os << "rock kinetic energy " << kinetic << " J above ten times the work done on it plus "
         << "the start-up allowance (" << work << " + " << watch_.energy_floor
         << " J), fastest particle |v| = " << v_max << " m/s";
      fail(observer, os.str(), i_v, too_large);
    }
    // the step in use is fixed; the stable one shrinks when particles approach the wave speed or
    // smoothing lengths collapse
    const double dt_stable = watch_.tssfac * dt_min;
    if (dt_stable < 0.5 * watch_.time_step)
    {
      std::ostringstream os;
      os << "collapsing time step: the stable step " << dt_stable << " s fell below half the step "
         << "in use " << watch_.time_step << " s (|v| = " << v[i_dt].norm()
         << " m/s, h = " << h[i_dt] << " m)";
      fail(observer, os.str(), i_dt, too_large);
    }
    for (const auto &[name, steel] : watch_.steel)
    {
      if (std::isfinite(steel->reaction_force() + steel->kinetic_energy() +
                        steel->loaded_face_displacement()))
        continue;
      std::ostringstream os;
      os << "non-finite state of the " << name << " (reaction " << steel->reaction_force()
         << " N, kinetic energy " << steel->kinetic_energy() << " J, loaded-face displacement "
         << steel->loaded_face_displacement() << " m)";
      const std::vector<double> xc = steel->contact_positions();
      for (std::size_t j = 0; j < xc.size() / 3; ++j)
        if (!std::isfinite(xc[3 * j] + xc[3 * j + 1] + xc[3 * j + 2]))
        {
          os << ", first non-finite contact node " << j;
          break;
        }
      fail(observer, os.str(), -1,
           "a steel time step above its stable limit or a contact stiffness near its bound "
           "(Platens/Contact stiffness scale)");
    }
    keep_last_good();
  }

  void RunLoop::keep_last_good()
  {
    // buffers reused, no allocation per step
    const sph::Body<3> &body = *watch_.rock;
    const auto &x            = body.positions();
    const auto &v            = body.velocities();
    const auto &x0           = body.reference_positions();
    const unsigned int n     = body.n_particles();
    last_good_.n             = n;
    last_good_.position.resize(3 * n);
    last_good_.velocity.resize(3 * n);
    last_good_.displacement.resize(3 * n);
    last_good_.stress.resize(6 * n);
    last_good_.plastic_strain.resize(n);
    last_good_.damage.resize(n);
    last_good_.failure_mode.resize(n);
    // a distributed rock: the owned particles' rows (the only ones gathered in `fail`)
    const std::uint8_t *owned = watch_.domain ? watch_.domain->owned().data() : nullptr;
#pragma omp parallel for schedule(static)
    for (long i = 0; i < static_cast<long>(n); ++i)
    {
      if (owned && !owned[i])
        continue;
      for (int d = 0; d < 3; ++d)
      {
        last_good_.position[3 * i + d]     = x[i][d];
        last_good_.velocity[3 * i + d]     = v[i][d];
        last_good_.displacement[3 * i + d] = x[i][d] - x0[i][d];
      }
      const auto &t      = body.stress3(i);
      const double s6[6] = {t(0, 0), t(1, 1), t(2, 2), t(1, 2), t(0, 2), t(0, 1)};
      std::copy(s6, s6 + 6, last_good_.stress.begin() + 6 * i);
      last_good_.plastic_strain[i] = body.plastic_strain(i);
      last_good_.damage[i]         = body.damage(i);
      last_good_.failure_mode[i]   = static_cast<int>(body.history(i).failure_mode);
    }
    last_good_step_ = test_.n_steps();
    last_good_time_ = test_.time();
  }
} // namespace coupling
