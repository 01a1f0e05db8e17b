// The coupled simulator in `cosim diagnose`: each held-out specimen run as a case of the coupled
// simulator (run_case) with the baseline rock and with the extended one, its curve and peak put
// against the measured ones (see diagnose_model.h, simulate()).
#include "diagnose_model.h"

#include <coupling/errors.h>
#include <coupling/run_case.h>
#include <coupling/run_output.h>
#include <sph/rock_models.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

namespace diagnose
{
  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    std::string num(const double v)
    {
      char b[32];
      std::snprintf(b, sizeof b, "%.7g", v);
      return b;
    }

    /// Particle spacing of a specimen's run [m]: the one asked for, coarsened so that a cylinder
    /// has at most 20 particles across (a 150 mm core at 2.5 mm would be 1.3 million particles;
    /// the rock model has no length scale of its own in its strength), and fine enough that 10
    /// span the specimen's smallest dimension (the case reader's rule).
    double spacing_of(const SimulatorTarget &t, const double spacing)
    {
      const double dx = std::max(spacing, t.diameter * 1e-3 / 20.0);
      return std::min(dx, std::min(t.diameter, t.length) * 1e-3 / 10.0);
    }

    /// A regula falsi bracket of a root, f(lo) <= 0 <= f(hi), moved by the Illinois rule (the end
    /// kept twice in a row has its value halved).
    struct Illinois
    {
      double lo, f_lo, hi, f_hi;
      int side = 0;

      double next() const { return (lo * f_hi - hi * f_lo) / (f_hi - f_lo); }

      void update(const double x, const double f)
      {
        if (f < 0)
        {
          lo = x, f_lo = f;
          if (side == -1)
            f_hi /= 2;
          side = -1;
        }
        else
        {
          hi = x, f_hi = f;
          if (side == 1)
            f_lo /= 2;
          side = 1;
        }
      }
    };

    /// Rocks of a heterogeneous case whose mean is its result (Rock/Scatter seed 1, 2, 3): one
    /// rock's end-friction effect on a short specimen moves by +-5 % (seed 1-3, mu 0.32, L/D 1/2,
    /// G_I 100 J/m^2: 1.085 / 1.191 / 1.169 x its standard specimen, measured with hourglass
    /// forces across the softening particles, SPH/Hourglass fading = false)
    constexpr int realisations = 3;

    /// The edge of the heterogeneous rock's strength cells [m]: 5 mm, fixed in space (a finer
    /// spacing resolves the same rock), or the spacing where that is coarser.
    double cell_of(const double dx) { return std::max(5e-3, dx); }

    /// The case file's "Section/Key=value" lines of a specimen with a rock (a heterogeneous rock:
    /// its realisation `seed`).
    std::vector<std::string> overrides_of(const SimulatorTarget &t, const SimulatedRock &r,
                                          const double dx, const int seed = 0)
    {
      const bool bts = t.test == "BTS";
      std::vector<std::string> o = {
        std::string("Test/Type=") + (bts ? "BTS" : (t.sigma3 > 0 ? "CTCS" : "UCS")),
        "Test/Diameter=" + num(t.diameter * 1e-3),
        "Test/Length=" + num(t.length * 1e-3),
        "Test/Confining pressure=" + num(bts ? 0.0 : t.sigma3 * 1e6),
        "Rock/Youngs modulus=" + num(r.E * 1e6),
        "Rock/Poissons ratio=" + num(r.nu),
        "Rock/Density=" + num(r.density)};
      const double ucs = r.ucs * r.strength_factor * r.calibration_factor;
      const double sp = std::sin(r.phi * pi / 180), cp = std::cos(r.phi * pi / 180);
      const double c = ucs * (1 - sp) / (2 * cp);
      o.push_back("Rock/Cohesion=" + num(c * 1e6));
      o.push_back("Rock/Friction angle=" + num(r.phi));
      if (r.hoek_brown)
      {
        o.push_back("Rock/Model=hoek-brown");
        o.push_back("Rock/UCS=" + num(ucs * 1e6));
        o.push_back("Rock/Hoek-Brown mi=" + num(r.m_i));
      }
      else
        o.push_back(std::string("Rock/Model=") +
                    (r.tensile > 0 ? "mohr-coulomb-cutoff" : "mohr-coulomb"));
      if (r.tensile > 0)
      {
        // Mohr-Coulomb with a cut-off above its apex c / tan(phi) is Mohr-Coulomb: held there
        const double t0 = r.tensile * r.strength_factor * r.calibration_factor;
        o.push_back("Rock/Tensile strength=" +
                    num(1e6 * (r.hoek_brown ? t0 : std::min(t0, c / std::tan(r.phi * pi / 180)))));
      }
      if (r.closure_ratio < 1)
      {
        o.push_back("Rock/Closure modulus ratio=" + num(r.closure_ratio));
        o.push_back("Rock/Closure stress=" + num(r.closure_stress * 1e6));
      }
      if (r.k_frame > 0)
        o.push_back("Platens/Frame stiffness=" + num(r.k_frame * 1e6)); // kN/mm -> N/m
      if (r.friction > 0)
        o.push_back("Platens/Friction coefficient=" + num(r.friction));
      if (r.weibull_m > 0)
      {
        o.push_back("Rock/Softening law=fracture energy");
        o.push_back("Rock/Strength scatter=" + num(r.weibull_m));
        o.push_back("Rock/Scatter length=" + num(cell_of(dx)));
        o.push_back("Rock/Scatter seed=" + std::to_string(seed));
      }
      o.push_back("SPH/Particle spacing=" + num(dx));
      o.push_back("Loading/End strain=" + num(t.end_strain));
      o.push_back("Output/Snapshots=0");
      return o;
    }

    /// A run of a heterogeneous rock's fit went unstable: where (`what`), and its case file.
    struct FitUnstable
    {
      std::string what, case_text;
    };

    /// Keeps the history rows of a run.
    class Recorder : public coupling::RunObserver
    {
    public:
      void history(const coupling::HistoryRow &row) override { rows.push_back(row); }
      std::vector<coupling::HistoryRow> rows;
    };

    /// Displacement [mm] at which `curve` first carries `force` [kN] before its peak; the
    /// displacement at its peak where it never does.
    double displacement_at(const SimulatedRun &run, const double force)
    {
      const auto &f       = run.force_kN;
      const auto &d       = run.displacement_mm;
      const std::size_t n = f.size();
      if (n == 0)
        return 0;
      const std::size_t ip = static_cast<std::size_t>(std::max_element(f.begin(), f.end()) - f.begin());
      for (std::size_t i = 1; i <= ip; ++i)
        if (f[i] >= force && f[i] > f[i - 1])
        {
          const double w = std::clamp((force - f[i - 1]) / (f[i] - f[i - 1]), 0.0, 1.0);
          return d[i - 1] + w * (d[i] - d[i - 1]);
        }
      return force <= f.front() ? d.front() : d[ip];
    }

    /// The characteristic length E G_I / f_t^2 of a case's rock [m] (the default case's M1 basalt
    /// at 100 J/m^2: 40.8 mm).
    double characteristic_length(const coupling::CaseParameters &c)
    {
      const double f_t = sph::rock::uniaxial_tensile_strength(c.rock);
      return c.rock.youngs_modulus * c.rock.fracture_energy / (f_t * f_t);
    }

    /// Runs a case: its case file (without the header), curve and peak; no errors yet.
    SimulatedRun execute(const SimulatorTarget &t, const SimulatedRock &r, const Options &options,
                         const double dx, const int seed, std::vector<double> &time_s)
    {
      SimulatedRun out;
      coupling::CaseParameters c;
      std::vector<std::string> overrides = overrides_of(t, r, dx, seed);
      if (r.weibull_m > 0)
      {
        // the heterogeneous rock's brittleness is its characteristic length E G_I / f_t^2 (so
        // that a strength scale k scales G_I by k^2); this rock's f_t is read without the crack
        // band (whose check needs its G_I)
        if (!(r.characteristic_length > 0))
          throw std::logic_error("diagnose: a heterogeneous rock runs with its characteristic length");
        const double l_ch = r.characteristic_length;
        std::string unused;
        std::vector<std::string> plain;
        for (const auto &line : overrides)
          if (line.rfind("Rock/Softening law=", 0) != 0)
            plain.push_back(line);
        options.read_case(plain, c, unused);
        const double f_t = sph::rock::uniaxial_tensile_strength(c.rock);
        overrides.push_back("Rock/Fracture energy=" + num(l_ch * f_t * f_t / c.rock.youngs_modulus));
        c = coupling::CaseParameters();
      }
      options.read_case(overrides, c, out.case_text); // Output/Snapshots=0 among them
      c.output.progress = false;
      Recorder rec;
      try
      {
        const coupling::Summary s = coupling::run_case(c, rec);
        out.peak_MPa              = s.peak_stress / 1e6;
        out.stop_reason           = s.stop_reason;
      }
      catch (const coupling::InstabilityError &e)
      {
        // one unstable run does not end the diagnosis: the specimen is reported and left out of
        // the gain (its peak so far is not a peak: the run may not have reached it)
        out.unstable    = true;
        out.stop_reason = std::string("unstable: ") + e.what();
        for (const auto &row : rec.rows)
          out.peak_MPa = std::max(out.peak_MPa, row.stress / 1e6);
      }
      // the curve from the start of the deviatoric load (CTCS: after the confinement), in the
      // data's units: deviatoric force (BTS: the load) and the displacement where it was read
      const bool bts    = t.test == "BTS";
      const double area = pi * t.diameter * t.diameter / 4; // [mm^2]
      std::vector<double> q, d;
      for (const auto &row : rec.rows)
      {
        q.push_back(bts ? row.force / 1e3 : (row.stress / 1e6 - t.sigma3) * area / 1e3);
        d.push_back(t.platen || bts ? row.displacement * 1e3 : row.axial_gauge_strain * t.length);
      }
      if (q.empty())
        return out;
      const std::size_t ip = static_cast<std::size_t>(std::max_element(q.begin(), q.end()) - q.begin());
      std::size_t i0       = 0;
      for (std::size_t i = 0; i < ip; ++i)
        if (q[i] <= 2e-3 * q[ip])
          i0 = i;
      for (std::size_t i = i0; i < q.size(); ++i)
      {
        out.force_kN.push_back(q[i]);
        out.displacement_mm.push_back(d[i] - d[i0]);
        time_s.push_back(rec.rows[i].time);
      }
      return out;
    }

    /// Linear interpolation of `y(x)` at `at` (x increasing; held at its ends).
    double interpolate(const std::vector<double> &x, const std::vector<double> &y, const double at)
    {
      const auto it = std::upper_bound(x.begin(), x.end(), at);
      if (it == x.begin())
        return y.front();
      if (it == x.end())
        return y.back();
      const std::size_t i = static_cast<std::size_t>(it - x.begin());
      return y[i - 1] + (y[i] - y[i - 1]) * (at - x[i - 1]) / (x[i] - x[i - 1]);
    }

    /// The mean of the realisations of a heterogeneous rock: the mean peak, and the mean curve at
    /// the first one's times up to the shortest run's end (they load on one schedule); its case
    /// file and stop reason are the first one's, or the stop reason of a run that failed (of one
    /// that went unstable: its case file too).
    SimulatedRun mean_of(const std::vector<SimulatedRun> &runs,
                         const std::vector<std::vector<double>> &times)
    {
      SimulatedRun out = runs.front();
      out.force_kN.clear();
      out.displacement_mm.clear();
      out.peak_MPa = 0;
      out.unstable = false; // set below, with the rock that went unstable
      double end   = times.front().empty() ? 0 : times.front().back();
      for (std::size_t k = 0; k < runs.size(); ++k)
      {
        out.peak_MPa += runs[k].peak_MPa / runs.size();
        end = std::min(end, times[k].empty() ? 0 : times[k].back());
        if (out.unstable) // the first rock that went unstable is the one reported
          continue;
        if (runs[k].unstable)
        {
          out.unstable    = true;
          out.stop_reason = "rock " + std::to_string(k + 1) + " " + runs[k].stop_reason;
          out.case_text   = runs[k].case_text; // the case that went unstable, to re-run
        }
        else if (runs[k].stop_reason != "post-peak drop" && runs[k].stop_reason != "end strain")
          out.stop_reason = runs[k].stop_reason;
      }
      for (const double at : times.front())
      {
        if (at > end)
          break;
        double f = 0, d = 0;
        for (std::size_t k = 0; k < runs.size(); ++k)
        {
          f += interpolate(times[k], runs[k].force_kN, at) / runs.size();
          d += interpolate(times[k], runs[k].displacement_mm, at) / runs.size();
        }
        out.force_kN.push_back(f);
        out.displacement_mm.push_back(d);
      }
      return out;
    }

    /// The errors of a run against the measured specimen, and its case file's header.
    void score(const SimulatorTarget &t, const SimulatedRock &r, SimulatedRun &run)
    {
      std::string head = "# written by cosim diagnose for specimen " + t.name +
                         ": the rock's values are set below (Rock/Group names the data "
                         "tables' group only for what is not)\n";
      for (const auto &n : r.notes)
        head += "# " + n + "\n";
      run.case_text = head + run.case_text;
      // a specimen gives two measurements, its strength and its deformation curve: its error is
      // the RMS of the two parts (peak residual / noise; RMS over the curve's points of residual
      // / noise), so twenty points of one curve do not outweigh the strength
      double ss_parts = 0, ss_points = 0, ss_curve = 0;
      int parts       = 0;
      if (t.has_peak)
      {
        ss_parts += std::pow((run.peak_MPa - t.measured_peak) / t.peak_noise, 2);
        ++parts;
      }
      for (std::size_t k = 0; k < t.points.size(); ++k)
      {
        const double e = displacement_at(run, t.points[k].force) - t.points[k].measured;
        ss_points += std::pow(e / t.point_noise[k], 2);
        ss_curve += e * e;
      }
      if (!t.points.empty())
      {
        ss_parts += ss_points / t.points.size();
        ++parts;
      }
      run.error        = parts > 0 ? std::sqrt(ss_parts / parts) : 0;
      run.curve_rms_mm = t.points.empty() ? 0 : std::sqrt(ss_curve / t.points.size());
    }
  } // namespace

  void simulate(const std::vector<SimulatorTarget> &targets, const Options &options,
                Diagnosis &out)
  {
    if (!options.read_case)
      throw std::logic_error("diagnose: Options::read_case is needed to run the coupled simulator");
    if (targets.empty())
    {
      out.notes.push_back("coupled simulator: not run; the baseline misses no specimen by more "
                          "than three of the data's noise SDs");
      return;
    }
    // a case runs once (the baselines of one geometry and confinement repeat)
    std::map<std::string, std::pair<SimulatedRun, std::vector<double>>> done;
    const auto once = [&](const SimulatorTarget &t, const SimulatedRock &r, const double dx,
                          const int seed) {
      std::string key = "characteristic length " + num(r.characteristic_length) + "\n";
      for (const auto &line : overrides_of(t, r, dx, seed))
        key += line + "\n";
      auto it = done.find(key);
      if (it == done.end())
      {
        std::vector<double> time_s;
        SimulatedRun result = execute(t, r, options, dx, seed, time_s);
        it = done.emplace(key, std::pair{result, time_s}).first;
      }
      return it->second;
    };
    // a heterogeneous rock: the mean of its realisations
    const auto mean_run = [&](const SimulatorTarget &t, const SimulatedRock &r, const double dx) {
      std::vector<SimulatedRun> runs;
      std::vector<std::vector<double>> times;
      for (int seed = 1; seed <= realisations; ++seed)
      {
        const auto &[result, time_s] = once(t, r, dx, seed);
        runs.push_back(result);
        times.push_back(time_s);
      }
      return mean_of(runs, times);
    };
    // The heterogeneous rock runs at 5 mm or the spacing asked for, whichever is coarser: its
    // fit takes about thirty runs (at 2.5 mm the benchmark folder's took over 40 CPU minutes),
    // and it is the simulator's at the spacing it is fitted at (strength and brittleness fitted
    // there, held-out specimens run there)
    const double het_spacing = std::max(options.coupled_spacing, 5e-3);
    // a heterogeneous rock's fit: its characteristic length [m], strength scale and the
    // simulator's friction coefficient
    struct RockFit
    {
      double l = 0, k = 0, mu = 0;
    };
    std::map<std::string, RockFit> fits;
    std::map<std::string, FitUnstable> stopped; // the fits that a run's instability stopped
    double last_l = 0; // the last fitted characteristic length [m] (the next fit starts there)
    const auto run = [&](const SimulatorTarget &t, SimulatedRock r, const double dx) {
      SimulatedRun result;
      if (r.weibull_m > 0)
      {
        // The simulator's own two numbers of the rock: its brittleness, the characteristic
        // length l = E G_I / f_t^2, and a strength scale k, fitted to what the extended model
        // (fitted without this specimen) says of a standard 50 x 100 mm specimen and of the
        // data's shortest one, with the model's mu (0.3 and more holds the faces: the curves'
        // stiffening is then that of held ends). l so that the short specimen's strength over
        // the standard one's is the model's ratio (held ends confine a ductile rock more; k does
        // not change the ratio: strengths and G_I scale together), then k for the standard one;
        // each the mean of the rock's realisations at the specimen's own spacing.
        const auto specimen = [&t](const double D, const double L) {
          SimulatorTarget x = t;
          x.test            = "UCS";
          x.diameter        = D;
          x.length          = L;
          x.sigma3          = 0;
          x.end_strain      = 0.01;
          return x;
        };
        const bool fit_l               = r.short_length > 0; // else the case's rock's l
        const SimulatorTarget standard = specimen(50, 100);
        const SimulatorTarget shortest = fit_l ? specimen(r.short_diameter, r.short_length) : standard;
        const double dx_standard       = spacing_of(standard, het_spacing);
        const double dx_short          = spacing_of(shortest, het_spacing);
        SimulatedRock unit             = r;
        unit.strength_factor           = 1;
        unit.calibration_factor        = 1;
        std::string key;
        for (const auto &line : overrides_of(standard, unit, dx_standard))
          key += line + "\n";
        key += num(r.short_peak) + " " + num(r.calibration_peak) + " " + num(r.short_diameter) +
               " " + num(r.short_length);
        if (!fits.count(key))
        {
          try
          {
            const double target = fit_l ? r.short_peak / r.calibration_peak : 1.0;
            std::map<std::pair<double, double>, std::pair<double, double>> peaks; // (log l, mu) -> standard, short
            double mu = r.friction; // the model's; lowered only where no l reaches the ratio
            const auto ratio_at = [&](const double log_l) {
              SimulatedRock x         = unit;
              x.characteristic_length = std::exp(log_l);
              x.friction              = mu;
              const SimulatedRun sa = mean_run(standard, x, dx_standard);
              const SimulatedRun sb = fit_l ? mean_run(shortest, x, dx_short) : sa;
              for (const SimulatedRun *u : {&sa, &sb})
                if (u->unstable)
                  throw FitUnstable{"at E G_I / f_t^2 = " + num(x.characteristic_length) + " m the " +
                                      num(u == &sa ? standard.diameter : shortest.diameter) + " x " +
                                      num(u == &sa ? standard.length : shortest.length) +
                                      " mm specimen's " + u->stop_reason,
                                    u->case_text};
              const double a = sa.peak_MPa, b = sb.peak_MPa;
              if (!(a > 0 && b > 0))
                throw std::runtime_error("diagnose: the heterogeneous rock's specimens carried no "
                                         "load; its brittleness and strengths cannot be fitted");
              peaks[{log_l, mu}] = {a, b};
              return b / a - target;
            };
            // l from just above the snap-back limit of the coarser crack band (l > h / 2) to 1 m:
            // from the last fit's l (first: the case's rock's), steps of x4 until the ratio is
            // bracketed, then regula falsi (Illinois) on log l to 0.3 % of the ratio (a seventh of
            // the data's strength noise)
            coupling::CaseParameters own; // the case's own rock and numerics
            std::string unused;
            options.read_case({}, own, unused);
            const double band = sph::rock::crack_band_width(std::max(dx_standard, dx_short), own.sph.cslh);
            const double x_min = std::log(0.55 * band), x_max = std::log(1.0);
            // a fit starts from the last fit's l; without one (no short specimen) l is the case's
            double x = std::clamp(std::log(fit_l && last_l > 0 ? last_l : characteristic_length(own)),
                                  x_min, x_max);
            if (fit_l)
            {
              double f = ratio_at(x);
              double lo = x, hi = x, f_lo = f, f_hi = f;
              // widen: a more ductile rock (larger l) is confined more by the held ends
              while (std::abs(f) >= 3e-3 * target && f_lo > 0 && lo > x_min)
              {
                hi = lo, f_hi = f_lo;
                lo = std::max(x_min, lo - std::log(4.0)), f_lo = ratio_at(lo);
              }
              while (std::abs(f) >= 3e-3 * target && f_hi < 0 && hi < x_max)
              {
                lo = hi, f_lo = f_hi;
                hi = std::min(x_max, hi + std::log(4.0)), f_hi = ratio_at(hi);
              }
              bool found = std::abs(f) < 3e-3 * target;
              const bool too_confined = !found && f_lo >= 0;
              if (too_confined)
                x = lo, found = true; // even the most brittle rock is confined too much
              if (!found && f_hi <= 0)
                x = hi, found = true; // even the most ductile rock is confined too little
              Illinois on_l{lo, f_lo, hi, f_hi};
              for (int it = 0; !found && it < 12; ++it)
              {
                x     = on_l.next();
                f     = ratio_at(x);
                found = std::abs(f) < 3e-3 * target || on_l.hi - on_l.lo < 1e-3;
                on_l.update(x, f);
              }
              last_l = std::exp(x);
              if (too_confined && f_lo >= 3e-3 * target)
              {
                // Then the simulator's friction is what reproduces the data's ratio at that l:
                // the data's mu is Siebel's (the model's), and the simulator's held ends confine
                // more than Siebel says (frictionless ends give the ratio 1, below the target).
                // Regula falsi (Illinois) on mu in [0, the model's mu] to the same 0.3 %.
                mu = 0;
                Illinois on_mu{0, ratio_at(x), r.friction, f_lo};
                // (its lower end stays below the target once it is: frictionless ends at or
                // above it leave mu 0, nothing lower to look for)
                for (int it = 0; it < 12 && on_mu.f_lo < 0; ++it)
                {
                  mu             = on_mu.next();
                  const double g = ratio_at(x);
                  if (std::abs(g) < 3e-3 * target)
                    break;
                  on_mu.update(mu, g);
                }
              }
            }
            if (!peaks.count({x, mu}))
              ratio_at(x);
            const auto [a, b] = peaks.at({x, mu});
            fits[key]         = {std::exp(x), r.calibration_peak / a, mu};
            out.notes.push_back(
              "coupled simulator: end friction mu " + num(r.friction) +
              (mu != r.friction ? " (the simulator's " + num(mu) +
                                    ": even its most brittle rock is confined more at the "
                                    "model's)"
                                : std::string()) +
              " on a heterogeneous rock (mean of " + std::to_string(realisations) +
              " rocks) of characteristic length E G_I / f_t^2 = " + num(std::exp(x)) + " m" +
              (fit_l ? ", fitted: its " + num(r.short_diameter) + " x " + num(r.short_length) +
                         " mm specimen carries " + num(b / a) +
                         " x its standard one's strength (the model: " + num(target) + ")"
                     : " (the case's rock's)") +
              "; strengths x " + num(r.calibration_peak / a) + " for the standard " +
              num(r.calibration_peak) + " MPa");
          }
          catch (const FitUnstable &e)
          {
            fits[key] = {std::nan(""), std::nan(""), std::nan("")};
            stopped[key] = e;
            out.notes.push_back("coupled simulator: the fit of the heterogeneous rock for end "
                                "friction mu " + num(r.friction) + " stopped, " + e.what +
                                "; its specimens' extended cases are not run (each one's case "
                                "file is the unstable run's)");
          }
        }
        if (stopped.count(key))
        {
          result.unstable    = true;
          result.stop_reason = "not run: the fit of its rock stopped, " + stopped[key].what;
          result.case_text   = "# the fit of this specimen's rock stopped at this case, " +
                             stopped[key].what + "\n" + stopped[key].case_text;
        }
        else
        {
          r.characteristic_length = fits[key].l;
          r.calibration_factor    = fits[key].k;
          r.friction              = fits[key].mu;
          result                  = mean_run(t, r, spacing_of(t, het_spacing));
        }
      }
      else
        result = once(t, r, dx, 0).first;
      score(t, r, result);
      return result;
    };
    double ss_b = 0, ss_e = 0, sp_b = 0, sp_e = 0, sc_b = 0, sc_e = 0;
    int n_peak = 0, n_curve = 0;
    for (const auto &t : targets)
    {
      Simulation sim;
      sim.name             = t.name;
      sim.test             = t.test;
      sim.group            = t.group;
      sim.diameter_mm      = t.diameter;
      sim.length_mm        = t.length;
      sim.confining_MPa    = t.test == "BTS" ? 0 : t.sigma3;
      sim.particle_spacing = spacing_of(t, options.coupled_spacing);
      sim.measured_peak_MPa = t.has_peak ? t.measured_peak : std::nan("");
      sim.n_points         = static_cast<int>(t.points.size());
      if (t.curve != nullptr)
      {
        sim.measured_displacement_mm = t.curve->displacement;
        sim.measured_force_kN        = t.curve->force;
      }
      sim.baseline = run(t, t.baseline, sim.particle_spacing);
      sim.extended = run(t, t.extended, sim.particle_spacing);
      out.simulations.push_back(sim);
      if (left_out(sim))
        continue;
      ss_b += std::pow(sim.baseline.error, 2);
      ss_e += std::pow(sim.extended.error, 2);
      if (t.has_peak)
      {
        sp_b += std::pow(sim.baseline.peak_MPa - t.measured_peak, 2);
        sp_e += std::pow(sim.extended.peak_MPa - t.measured_peak, 2);
        ++n_peak;
      }
      if (!t.points.empty())
      {
        sc_b += std::pow(sim.baseline.curve_rms_mm, 2);
        sc_e += std::pow(sim.extended.curve_rms_mm, 2);
        ++n_curve;
      }
    }
    const int n_unstable = coupled_unstable(out);
    const bool none_left = n_unstable == static_cast<int>(targets.size());
    const double n       = std::max<double>(targets.size() - n_unstable, 1);
    for (auto [e, ss, sp, sc] : {std::tuple{&out.baseline, ss_b, sp_b, sc_b},
                                 std::tuple{&out.extended, ss_e, sp_e, sc_e}})
    {
      e->coupled["error"] = std::sqrt(ss / n);
      if (n_peak > 0)
        e->coupled["strength_rms_MPa"] = std::sqrt(sp / n_peak);
      if (n_curve > 0)
        e->coupled["curve_rms_mm"] = std::sqrt(sc / n_curve);
    }
    out.coupled_gain = ss_e > 0 ? std::sqrt(ss_b / ss_e) : 1;
    if (none_left)
    {
      out.coupled_gain = std::nan("");
      for (auto *e : {&out.baseline, &out.extended})
        e->coupled.clear();
    }
    out.notes.push_back(
      "coupled simulator: " + std::to_string(targets.size()) + " specimens, " +
      std::to_string(done.size()) + " runs (run_case at spacing " + num(options.coupled_spacing) +
      " m, a cylinder at most 20 particles across); each extended case's parameters fitted "
      "without its specimen; size and rate enter as a strength factor of the specimen (the "
      "simulator loads at its own quasi-static rate); end friction on a heterogeneous rock, the "
      "mean of " + std::to_string(realisations) + " rocks, at spacing " + num(het_spacing) +
      " m or coarser");
    // a run that went unstable: its specimen is named, with where, and left out of the gain
    std::string unstable;
    for (std::size_t i = 0; i < out.simulations.size(); ++i)
    {
      const Simulation &m = out.simulations[i];
      for (const auto &[which, r] : {std::pair{"baseline", &m.baseline}, std::pair{"extended", &m.extended}})
        if (r->unstable)
          unstable += (unstable.empty() ? "" : "; ") + simulation_stem(i) + " (" + m.name + ", " +
                      m.test + ") " + which + ": " + r->stop_reason;
    }
    if (!unstable.empty())
      out.notes.push_back("coupled simulator: " + std::to_string(n_unstable) + " of " +
                          std::to_string(targets.size()) +
                          " specimens left out of the coupled gain, a run unstable: " + unstable +
                          (none_left ? "; no coupled gain" : ""));
    // where the extended case does worse than the baseline, the simulator does not carry what
    // the surrogate named: say where, so that the gain is not read as the surrogate's
    std::string worse;
    for (std::size_t i = 0; i < out.simulations.size(); ++i)
    {
      const Simulation &m = out.simulations[i];
      if (!left_out(m) && m.extended.error > 1.05 * m.baseline.error + 0.5)
        worse += (worse.empty() ? "" : ", ") + simulation_stem(i) + " (" + m.name + ", " +
                 m.test + ": error " + num(m.baseline.error) + " -> " + num(m.extended.error) + ")";
    }
    if (!worse.empty())
      out.notes.push_back("coupled simulator: the extended case is worse than the baseline on " +
                          worse +
                          ": there the simulator does not reproduce the named effect as the "
                          "surrogate models it");
  }
} // namespace diagnose
