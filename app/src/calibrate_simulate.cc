// `cosim calibrate --simulate`: the strength of a Mohr-Coulomb rock calibrated through the
// coupled simulator, so that the simulated UCS (the mean over rocks of a scattered strength) is
// the measured one. A heterogeneous rock fails below its particles' mean strength (weak cells
// yield first and a band runs through them), so the closed-form calibration of Eqs. 14-15 does not
// hold for it; this one does, for the model as the simulator runs it.
#include "calibrate_simulate.h"

#include <app/case_file.h>
#include <app/cli.h>
#include <coupling/errors.h>
#include <coupling/run_case.h>
#include <diagnose/text_input.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <stdexcept>
#include <vector>

namespace app
{
  using coupling::CaseParameters;
  using coupling::InputError;

  namespace
  {
    struct Options
    {
      std::string case_file, check_file;
      std::vector<std::string> overrides;
      int seeds = 3;
      double target = 0;     ///< [Pa]; 0 = the group's Table 3 UCS
      double tolerance = 0.005; ///< relative miss of the mean peak at which the iteration stops
      bool csv = false;
    };

    /// The case's plastic strengths times k: c and the tension cut-off (where there is one).
    CaseParameters scaled(CaseParameters p, const double k)
    {
      p.rock.cohesion *= k;
      p.rock.tensile_strength *= k;
      return p;
    }

    struct Sample
    {
      std::vector<double> peaks; ///< [Pa] one per seed
      double mean = 0, standard_error = 0; ///< [Pa]
    };

    /// Runs `p` once per seed (seed, seed + 1, ...; one run for a homogeneous rock) and collects
    /// the peaks; `what` names the runs in the progress lines on stderr.
    Sample sample(CaseParameters p, const int seeds, const std::string &what)
    {
      Sample s;
      const int n   = p.rock_case.strength_scatter > 0 ? seeds : 1;
      const int first = p.rock_case.scatter_seed;
      coupling::RunObserver quiet;
      for (int i = 0; i < n; ++i)
      {
        p.rock_case.scatter_seed = first + i;
        const coupling::Summary r = coupling::run_case(p, quiet);
        if (!(r.peak_stress > 0))
          throw std::runtime_error("cosim calibrate --simulate: " + what + ", seed " +
                                   std::to_string(first + i) + ": the run found no peak (" + r.stop_reason + ")");
        s.peaks.push_back(r.peak_stress);
        std::fprintf(stderr, "cosim calibrate: %s, seed %d: peak %.2f MPa (%zu steps, %.1f s)\n", what.c_str(),
                     first + i, r.peak_stress * 1e-6, r.n_steps, r.wall_seconds);
      }
      for (const double v : s.peaks)
        s.mean += v / n;
      if (n > 1)
      {
        double var = 0;
        for (const double v : s.peaks)
          var += (v - s.mean) * (v - s.mean) / (n - 1);
        s.standard_error = std::sqrt(var / n);
      }
      return s;
    }

    Options parse(const std::vector<std::string> &args)
    {
      Options o;
      ArgumentCursor cursor("calibrate", args);
      while (!cursor.done())
      {
        const std::string a = cursor.next();
        if (a == "--simulate")
          o.case_file = cursor.value(a);
        else if (a == "--check")
          o.check_file = cursor.value(a);
        else if (a == "--set")
          o.overrides.push_back(cursor.value(a));
        else if (a == "--seeds")
        {
          const double v = cursor.number(a);
          if (!(v >= 1 && v <= 100 && v == std::floor(v)))
            throw InputError("cosim calibrate: --seeds must be a whole number in [1, 100]");
          o.seeds = static_cast<int>(v);
        }
        else if (a == "--ucs")
        {
          o.target = cursor.number(a) * 1e6;
          if (!(o.target > 0))
            throw InputError("cosim calibrate: --ucs must be > 0 MPa");
        }
        else if (a == "--tolerance")
        {
          o.tolerance = cursor.number(a) / 100;
          if (!(o.tolerance >= 1e-4 && o.tolerance <= 0.2))
            throw InputError("cosim calibrate: --tolerance must be in [0.01, 20] %");
        }
        else if (a == "--csv")
          o.csv = true;
        else
          throw InputError("cosim calibrate --simulate: unknown option '" + diagnose::clip(a) + "'" +
                           did_you_mean(a, {"--simulate", "--check", "--set", "--seeds", "--ucs", "--tolerance", "--csv"}) +
                           "; accepted: --check, --set, --seeds, --ucs, --tolerance, --csv");
      }
      return o;
    }

    CaseParameters read_case(const std::string &file, const std::vector<std::string> &overrides,
                             const std::string &test)
    {
      CaseParameters p = read_case_file(file, overrides).parameters;
      if (p.test != test)
        throw InputError("cosim calibrate --simulate: " + file + ": Test/Type = " + p.test + "; " +
                         (test == "UCS" ? "the calibration runs a UCS case" : "--check runs a BTS case"));
      if (p.rock.model != sph::RockModel::mohr_coulomb && p.rock.model != sph::RockModel::mohr_coulomb_cutoff)
        throw InputError("cosim calibrate --simulate: " + file +
                         ": calibrates the cohesion (and tension cut-off) of Rock/Model = mohr-coulomb or "
                         "mohr-coulomb-cutoff");
      return p;
    }
  } // namespace

  bool is_simulated_calibration(const std::vector<std::string> &args)
  {
    for (const auto &a : args)
      if (ArgumentCursor::option_name(a) == "--simulate")
        return true;
    return false;
  }

  int calibrate_simulate_main(const std::vector<std::string> &args)
  {
    const Options o = parse(args);
    if (o.case_file.empty())
      throw InputError("cosim calibrate: --simulate needs a UCS case file");
    const CaseParameters base = read_case(o.case_file, o.overrides, "UCS");
    // the check case reads the same overrides: the same rock, another test
    const std::optional<CaseParameters> check =
      o.check_file.empty() ? std::nullopt : std::optional(read_case(o.check_file, o.overrides, "BTS"));
    const double target = o.target > 0 ? o.target : base.rock_case.ucs;
    if (!(target > 0))
      throw InputError("cosim calibrate --simulate: the case's group has no UCS; give --ucs MPa");

    // the peak grows with the strengths, less than in proportion when a heterogeneous rock's
    // fracture energy (fixed) makes the stronger rock more brittle: the first step takes it as
    // proportional (k <- k target / peak), the later ones a secant in log k, log peak through the
    // last two (slope kept within [0.2, 2])
    std::printf(o.csv ? "%s,%s,%s,%s,%s\n" : "%-9s %10s %12s %12s  %s\n", "iteration", "scale", "cohesion_MPa",
                "mean_UCS_MPa", "peaks_MPa");
    double k = 1, previous_k = 0, previous_mean = 0;
    Sample s;
    bool converged = false;
    for (int iteration = 0; iteration < 8; ++iteration)
    {
      s = sample(scaled(base, k), o.seeds, "UCS at scale " + std::to_string(k));
      std::string peaks;
      for (const double v : s.peaks)
      {
        char b[32];
        std::snprintf(b, sizeof b, "%s%.2f", peaks.empty() ? "" : (o.csv ? ";" : " "), v * 1e-6);
        peaks += b;
      }
      std::printf(o.csv ? "%d,%.6f,%.4f,%.3f,%s\n" : "%-9d %10.6f %12.4f %12.3f  %s\n", iteration, k,
                  base.rock.cohesion * k * 1e-6, s.mean * 1e-6, peaks.c_str());
      std::fflush(stdout);
      if (std::abs(s.mean / target - 1) <= o.tolerance)
      {
        converged = true;
        break;
      }
      double slope = 1; // d log(peak) / d log(k)
      if (previous_k > 0)
        slope = std::clamp(std::log(s.mean / previous_mean) / std::log(k / previous_k), 0.2, 2.0);
      previous_k    = k;
      previous_mean = s.mean;
      k *= std::pow(target / s.mean, 1 / slope);
    }
    const CaseParameters calibrated = scaled(base, k);
    std::printf("\ntarget UCS %.2f MPa: simulated %.2f MPa (%+.2f %%), standard error over %zu rock%s %.2f MPa\n",
                target * 1e-6, s.mean * 1e-6, 100 * (s.mean / target - 1), s.peaks.size(),
                s.peaks.size() == 1 ? "" : "s", s.standard_error * 1e-6);
    std::printf("strength scale %.4f of the case's; run with:\n  --set \"Rock/Cohesion=%.6g\"", k,
                calibrated.rock.cohesion);
    if (calibrated.rock.tensile_strength > 0)
      std::printf(" --set \"Rock/Tensile strength=%.6g\"", calibrated.rock.tensile_strength);
    std::printf("\n");
    if (check)
    {
      const Sample b = sample(scaled(*check, k), o.seeds, "check BTS");
      const double bts = check->rock_case.bts;
      std::printf("check %s: BTS %.2f MPa (standard error %.2f) against %.2f MPa measured (%+.2f %%)\n",
                  o.check_file.c_str(), b.mean * 1e-6, b.standard_error * 1e-6, bts * 1e-6,
                  100 * (b.mean / bts - 1));
    }
    if (!converged)
    {
      std::fprintf(stderr, "cosim calibrate --simulate: not converged to %.2f %% in 8 iterations\n",
                   100 * o.tolerance);
      return 1;
    }
    return 0;
  }
} // namespace app
