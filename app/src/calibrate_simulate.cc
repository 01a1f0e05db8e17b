// `cosim calibrate --simulate`: the strength of a Mohr-Coulomb rock calibrated through the
// coupled simulator, so that the simulated UCS (the mean over rocks of a scattered strength) is
// the measured one. A heterogeneous rock fails below its particles' mean strength (weak cells
// yield first and a band runs through them), so the closed-form calibration of Eqs. 14-15 does not
// hold for it; this one does, for the model as the simulator runs it.
#include "calibrate_simulate.h"
#include <app/joint_solver.h>

#include <app/case_file.h>
#include <app/cli.h>
#include <coupling/errors.h>
#include <coupling/run_case.h>
#include <diagnose/text_input.h>
#include <sph/rock_models.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
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
      std::string case_file, check_file, bts_file; ///< bts_file: --with-bts
      std::string cutoff_file;                      ///< --cutoff-from: a Hoek-Brown rock's disc
      std::string mb_file;                          ///< --mb-from: a Hoek-Brown rock's disc
      std::vector<std::string> overrides;
      int seeds = 3;
      double target = 0;     ///< [Pa]; 0 = the group's Table 3 UCS
      double bts_target = 0; ///< [Pa]; 0 = the group's Table 3 BTS (--with-bts)
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
        else if (a == "--with-bts")
          o.bts_file = cursor.value(a);
        else if (a == "--cutoff-from")
          o.cutoff_file = cursor.value(a);
        else if (a == "--mb-from")
          o.mb_file = cursor.value(a);
        else if (a == "--bts")
        {
          o.bts_target = cursor.number(a) * 1e6;
          if (!(o.bts_target > 0))
            throw InputError("cosim calibrate: --bts must be > 0 MPa");
        }
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
                           did_you_mean(a, {"--simulate", "--check", "--with-bts", "--cutoff-from", "--mb-from", "--bts", "--set",
                                            "--seeds", "--ucs", "--tolerance", "--csv"}) +
                           "; accepted: --check, --with-bts, --cutoff-from, --mb-from, --bts, --set, --seeds, --ucs, --tolerance, "
                           "--csv");
      }
      return o;
    }

    CaseParameters read_case(const std::string &file, const std::vector<std::string> &overrides,
                             const std::string &test, const bool hoek_brown = false)
    {
      CaseParameters p = read_case_file(file, overrides).parameters;
      if (p.test != test)
        throw InputError("cosim calibrate --simulate: " + file + ": Test/Type = " + p.test + "; " +
                         (test == "UCS" ? "the calibration runs a UCS case"
                                        : "--check, --with-bts, --cutoff-from and --mb-from run a BTS case"));
      if (hoek_brown)
      {
        if (p.rock.model != sph::RockModel::hoek_brown)
          throw InputError("cosim calibrate --cutoff-from, --mb-from: " + file +
                           ": calibrate a Hoek-Brown envelope: set Rock/Model = hoek-brown");
        return p;
      }
      if (p.rock.model != sph::RockModel::mohr_coulomb && p.rock.model != sph::RockModel::mohr_coulomb_cutoff)
        throw InputError("cosim calibrate --simulate: " + file +
                         ": calibrates the cohesion (and tension cut-off) of Rock/Model = mohr-coulomb or "
                         "mohr-coulomb-cutoff (--set \"Rock/Model=mohr-coulomb\"); a Hoek-Brown envelope's "
                         "cut-off or m_b: --cutoff-from or --mb-from");
      return p;
    }

    /// The rock keys that the UCS and the BTS case of a joint calibration must share.
    void require_same_rock(const CaseParameters &u, const CaseParameters &b, const std::string &bts_file)
    {
      const sph::MaterialParameters &x = u.rock, &y = b.rock;
      const coupling::RockCase &cx = u.rock_case, &cy = b.rock_case;
      const char *differs = x.model != y.model                         ? "Rock/Model"
                            : x.cohesion != y.cohesion                 ? "Rock/Cohesion"
                            : x.friction_angle != y.friction_angle     ? "Rock/Friction angle"
                            : x.tensile_strength != y.tensile_strength ? "Rock/Tensile strength"
                            : x.youngs_modulus != y.youngs_modulus     ? "Rock/Youngs modulus"
                            : x.softening_law != y.softening_law       ? "Rock/Softening law"
                            : x.fracture_energy != y.fracture_energy   ? "Rock/Fracture energy"
                            : cx.strength_scatter != cy.strength_scatter ? "Rock/Strength scatter"
                            : cx.scatter_length != cy.scatter_length   ? "Rock/Scatter length"
                            : cx.scatter_seed != cy.scatter_seed       ? "Rock/Scatter seed"
                            : x.hb_sigma_ci != y.hb_sigma_ci || x.hb_mb != y.hb_mb || x.hb_a != y.hb_a
                              ? "the Hoek-Brown envelope (Rock/Strength parameters, Rock/Hoek-Brown mi, a)"
                                                                       : nullptr;
      if (differs)
        throw InputError("cosim calibrate --with-bts: " + bts_file + ": " + differs +
                         " differs from the UCS case's: the two cases must describe one rock (set it in both, or by --set)");
    }

    /// The friction angle's coordinate of the joint fit: y = log tan(pi/4 + phi/2), the log of
    /// sqrt(N) in Mohr-Coulomb's UCS = 2 c sqrt(N), uniaxial tension = 2 c / sqrt(N).
    double friction_coordinate(const double phi) { return std::log(std::tan(M_PI / 4 + phi / 2)); }
    double friction_angle_of(const double y) { return 2 * std::atan(std::exp(y)) - M_PI / 2; }

    /// A friction angle below the dilation or residual friction angle (the reader refuses it)
    /// stops the fit.
    void require_friction_angle(const CaseParameters &p)
    {
      const double phi = p.rock.friction_angle;
      if (!(phi > 0 && phi < M_PI / 2) || p.rock.dilation_angle > phi ||
          (p.rock.residual_friction_angle > 0 && p.rock.residual_friction_angle > phi))
        throw std::runtime_error("cosim calibrate --with-bts: the fit reached a friction angle of " +
                                 std::to_string(phi * 180 / M_PI) +
                                 " degrees, outside (0, 90) or below Rock/Dilation angle or Rock/Residual friction angle");
    }

    /// Peaks [Pa] as MPa with two decimals, separated by spaces (csv: semicolons).
    std::string joined(const std::vector<double> &values, const bool csv)
    {
      std::string out;
      for (const double v : values)
      {
        char b[32];
        std::snprintf(b, sizeof b, "%s%.2f", out.empty() ? "" : (csv ? ";" : " "), v * 1e-6);
        out += b;
      }
      return out;
    }

    /// One strength scaled by k until the mean simulated peak of `run(k)` is `target` within
    /// --tolerance, at most 8 runs: the first step takes the peak as proportional to k (k <- k
    /// target / peak), the later ones a secant in log k, log peak through the last two (slope
    /// kept within [0.2, 2]: the peak grows less than in proportion when a heterogeneous rock's
    /// fixed fracture energy makes the stronger rock more brittle). Prints a row per run: the
    /// scaled value `base` k [MPa] (or `value(k)` where given) under `value_column`, the mean peak under `peak_column` with
    /// `peak_digits` decimals. k is the last scale run, not the next guess.
    struct ScaleFit
    {
      double k = 1;
      Sample sample;
      bool   converged = false;
    };
    ScaleFit fit_scale(const Options &o, const char *value_column, const char *peak_column, const int peak_digits,
                       const double base, const double target, const std::function<Sample(double)> &run,
                       const std::function<double(double)> &value = nullptr)
    {
      std::printf(o.csv ? "%s,%s,%s,%s,%s\n" : "%-9s %10s %12s %12s  %s\n", "iteration", "scale", value_column,
                  peak_column, "peaks_MPa");
      ScaleFit fit;
      double   k = 1, previous_k = 0, previous_mean = 0;
      for (int iteration = 0; iteration < 8; ++iteration)
      {
        fit.k      = k;
        fit.sample = run(k);
        const Sample &s = fit.sample;
        std::printf(o.csv ? "%d,%.6f,%.4f,%.*f,%s\n" : "%-9d %10.6f %12.4f %12.*f  %s\n", iteration, k,
                    value ? value(k) : base * k * 1e-6, peak_digits, s.mean * 1e-6, joined(s.peaks, o.csv).c_str());
        std::fflush(stdout);
        if (std::abs(s.mean / target - 1) <= o.tolerance)
        {
          fit.converged = true;
          break;
        }
        double slope = 1; // d log(peak) / d log(k)
        if (previous_k > 0)
          slope = std::clamp(std::log(s.mean / previous_mean) / std::log(k / previous_k), 0.2, 2.0);
        previous_k    = k;
        previous_mean = s.mean;
        k *= std::pow(target / s.mean, 1 / slope);
      }
      return fit;
    }

    /// --with-bts: c (with the cut-off) and phi together, the two unknowns of Eqs. 14-15, so that
    /// the mean simulated UCS and BTS are the measured ones: Broyden's method on the logarithms
    /// (joint_solver.h).
    int joint_calibration(const Options &o, const CaseParameters &ucs_case, const CaseParameters &bts_case,
                          const double ucs_target)
    {
      const double bts_target = o.bts_target > 0 ? o.bts_target : bts_case.rock_case.bts;
      if (!(bts_target > 0))
        throw InputError("cosim calibrate --with-bts: the case's group has no BTS; give --bts MPa");
      const double y0 = friction_coordinate(ucs_case.rock.friction_angle);
      const auto at   = [y0](const CaseParameters &p, const Vector2 &x) {
        CaseParameters q      = scaled(p, std::exp(x[0]));
        q.rock.friction_angle = friction_angle_of(y0 + x[1]);
        return q;
      };
      std::printf(o.csv ? "%s,%s,%s,%s,%s,%s,%s,%s\n" : "%-5s %9s %12s %9s %12s %12s  %s | %s\n", "run", "scale",
                  "cohesion_MPa", "phi_deg", "mean_UCS_MPa", "mean_BTS_MPa", "UCS_peaks_MPa", "BTS_peaks_MPa");
      Sample u, b;
      int evaluation = 0;
      const auto residual = [&](const Vector2 &x) -> Vector2 {
        const CaseParameters pu = at(ucs_case, x), pb = at(bts_case, x);
        require_friction_angle(pu);
        const double phi = pu.rock.friction_angle * 180 / M_PI;
        char what[96];
        std::snprintf(what, sizeof what, "c %.3f MPa, phi %.3f deg", pu.rock.cohesion * 1e-6, phi);
        u = sample(pu, o.seeds, std::string("UCS at ") + what);
        b = sample(pb, o.seeds, std::string("BTS at ") + what);
        std::printf(o.csv ? "%d,%.6f,%.4f,%.4f,%.3f,%.4f,%s,%s\n" : "%-5d %9.6f %12.4f %9.4f %12.3f %12.4f  %s | %s\n",
                    evaluation++, std::exp(x[0]), pu.rock.cohesion * 1e-6, phi, u.mean * 1e-6, b.mean * 1e-6,
                    joined(u.peaks, o.csv).c_str(), joined(b.peaks, o.csv).c_str());
        std::fflush(stdout);
        return {std::log(u.mean / ucs_target), std::log(b.mean / bts_target)};
      };
      // the first guess of the Jacobian is homogeneous Mohr-Coulomb's in (log c, y): log UCS =
      // log 2c + y and log(tension) = log 2c - y; Broyden's updates correct it for the disc's
      // stress state and the scatter. A step changes c by at most a factor 2 and y by 0.3 (phi by
      // a few degrees)
      const Matrix2 J0{{{1.0, 1.0}, {1.0, -1.0}}};
      const JointSolution j = solve_broyden(residual, {0, 0}, J0, std::log1p(o.tolerance), 12, 0.3);
      const CaseParameters c = at(ucs_case, j.x);
      std::printf("\ntarget UCS %.2f MPa: simulated %.2f MPa (%+.2f %%, standard error %.2f); target BTS %.2f MPa: "
                  "simulated %.2f MPa (%+.2f %%, standard error %.2f), over %zu rock%s\n",
                  ucs_target * 1e-6, u.mean * 1e-6, 100 * (u.mean / ucs_target - 1), u.standard_error * 1e-6,
                  bts_target * 1e-6, b.mean * 1e-6, 100 * (b.mean / bts_target - 1), b.standard_error * 1e-6,
                  u.peaks.size(), u.peaks.size() == 1 ? "" : "s");
      std::printf("c %.4f MPa, phi %.4f degrees; run with:\n  --set \"Rock/Cohesion=%.6g\" --set \"Rock/Friction "
                  "angle=%.6g\"",
                  c.rock.cohesion * 1e-6, c.rock.friction_angle * 180 / M_PI, c.rock.cohesion,
                  c.rock.friction_angle * 180 / M_PI);
      if (c.rock.tensile_strength > 0)
        std::printf(" --set \"Rock/Tensile strength=%.6g\"", c.rock.tensile_strength);
      std::printf("\n");
      if (!j.converged)
      {
        std::fprintf(stderr, "cosim calibrate --with-bts: not converged to %.2f %% in %d evaluations\n",
                     100 * o.tolerance, j.evaluations);
        return 1;
      }
      return 0;
    }

    /// One strength of a Hoek-Brown rock scaled by k (fit_scale) until the simulated BTS of the
    /// disc case is the measured one; then the UCS case runs once with it as a check.
    struct DiscScale
    {
      const char *option; ///< "--cutoff-from"
      const char *column;                                      ///< the scaled value's column
      std::function<double(double)> value;                     ///< its value at scale k
      std::function<CaseParameters(CaseParameters, double)> at; ///< the rock at scale k
      std::function<void(double)> report;                      ///< the result line(s) at scale k
    };
    int disc_scale_calibration(const Options &o, const CaseParameters &ucs_case, const CaseParameters &bts_case,
                               const double ucs_target, const double bts_target, const DiscScale &d)
    {
      const ScaleFit fit = fit_scale(
        o, d.column, "mean_BTS_MPa", 4, 0.0, bts_target,
        [&](const double k) {
          return sample(d.at(bts_case, k), o.seeds, std::string("BTS at ") + d.column + " " + std::to_string(d.value(k)));
        },
        d.value);
      const Sample &b = fit.sample;
      const Sample  u = sample(d.at(ucs_case, fit.k), o.seeds, "check UCS");
      std::printf("\ntarget BTS %.2f MPa: simulated %.2f MPa (%+.2f %%); check UCS %.2f MPa against %.2f MPa "
                  "(%+.2f %%)\n",
                  bts_target * 1e-6, b.mean * 1e-6, 100 * (b.mean / bts_target - 1), u.mean * 1e-6,
                  ucs_target * 1e-6, 100 * (u.mean / ucs_target - 1));
      d.report(fit.k);
      if (!fit.converged)
      {
        std::fprintf(stderr, "cosim calibrate %s: not converged to %.2f %% in 8 iterations\n", d.option,
                     100 * o.tolerance);
        return 1;
      }
      return 0;
    }

    /// The BTS a disc calibration aims at: --bts, else the case's group's.
    double disc_target(const Options &o, const CaseParameters &bts_case, const char *option)
    {
      const double bts_target = o.bts_target > 0 ? o.bts_target : bts_case.rock_case.bts;
      if (!(bts_target > 0))
        throw InputError(std::string("cosim calibrate ") + option + ": the case's group has no BTS; give --bts MPa");
      return bts_target;
    }

    /// --cutoff-from: a Hoek-Brown rock's tension cut-off alone, scaled until the simulated BTS
    /// of the disc case is the measured one (the envelope, which sets the UCS and the triaxial
    /// strengths, is not touched).
    int cutoff_calibration(const Options &o, const CaseParameters &ucs_case, const CaseParameters &bts_case,
                           const double ucs_target)
    {
      const double bts_target = disc_target(o, bts_case, "--cutoff-from");
      const double cutoff0    = bts_case.rock.tensile_strength;
      if (!(cutoff0 > 0))
        throw InputError("cosim calibrate --cutoff-from: " + o.cutoff_file +
                         ": calibrates the tension cut-off of Rock/Model = hoek-brown (Rock/Tensile strength > 0, "
                         "as Rock/Strength parameters = envelope sets it)");
      DiscScale d{"--cutoff-from", "cutoff_MPa", [cutoff0](const double k) { return cutoff0 * k * 1e-6; },
                  [](CaseParameters p, const double k) {
                    p.rock.tensile_strength *= k;
                    return p;
                  },
                  [cutoff0](const double k) {
                    std::printf("tension cut-off %.4f MPa (%.4f of the case's); run with:\n"
                                "  --set \"Rock/Tensile strength=%.6g\"\n",
                                cutoff0 * k * 1e-6, k, cutoff0 * k);
                  }};
      return disc_scale_calibration(o, ucs_case, bts_case, ucs_target, bts_target, d);
    }

    /// --mb-from: a Hoek-Brown rock's m_b alone, for a group without triaxial data (a = 1/2 and
    /// m_b through the disc centre's closed-form state, as Rock/Strength parameters = envelope
    /// gives it): no tension cut-off but the envelope's own apex sigma_ci / m_b, m_b divided by k
    /// until the simulated BTS of the disc case is the measured one (a smaller m_b: a stronger
    /// disc). sigma_ci stays the UCS.
    int mb_calibration(const Options &o, const CaseParameters &ucs_case, const CaseParameters &bts_case,
                       const double ucs_target)
    {
      const double bts_target = disc_target(o, bts_case, "--mb-from");
      if (bts_case.rock.hb_a != 0.5)
        throw InputError("cosim calibrate --mb-from: " + o.mb_file + ": the envelope has a = " +
                         std::to_string(bts_case.rock.hb_a) +
                         ", fitted to triaxial data; --mb-from is for a = 1/2 (a group without triaxial data), "
                         "--cutoff-from for a fitted envelope");
      const double mb0 = bts_case.rock.hb_mb, sci = bts_case.rock.hb_sigma_ci;
      DiscScale d{"--mb-from", "m_b", [mb0](const double k) { return mb0 / k; },
                  [mb0](CaseParameters p, const double k) {
                    p.rock.hb_mb            = mb0 / k;
                    p.rock.tensile_strength = 0;
                    return p;
                  },
                  [mb0, sci](const double k) {
                    // calibrated: sigma_ci = the UCS and the m_b, a given (envelope and simulated
                    // refuse an m_b of their own)
                    std::printf("m_b %.4f (the closed form's %.4f), no cut-off but the apex %.4f MPa; run with:\n"
                                "  --set \"Rock/Strength parameters=calibrated\" --set \"Rock/Hoek-Brown mi=%.6g\" "
                                "--set \"Rock/Hoek-Brown a=0.5\" --set \"Rock/Tensile strength=0\"\n",
                                mb0 / k, mb0, sci / (mb0 / k) * 1e-6, mb0 / k);
                  }};
      return disc_scale_calibration(o, ucs_case, bts_case, ucs_target, bts_target, d);
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
    if (!o.cutoff_file.empty() || !o.mb_file.empty())
    {
      const bool        mb   = !o.mb_file.empty();
      const std::string file = mb ? o.mb_file : o.cutoff_file;
      if (!o.check_file.empty() || !o.bts_file.empty() || (mb && !o.cutoff_file.empty()))
        throw InputError("cosim calibrate: --cutoff-from and --mb-from each calibrate on their own BTS case; "
                         "give one of them, without --check and --with-bts");
      const CaseParameters ucs  = read_case(o.case_file, o.overrides, "UCS", true);
      const CaseParameters disc = read_case(file, o.overrides, "BTS", true);
      require_same_rock(ucs, disc, file);
      const double target = o.target > 0 ? o.target : ucs.rock_case.ucs;
      if (!(target > 0))
        throw InputError("cosim calibrate --simulate: the case's group has no UCS; give --ucs MPa");
      return mb ? mb_calibration(o, ucs, disc, target) : cutoff_calibration(o, ucs, disc, target);
    }
    const CaseParameters base = read_case(o.case_file, o.overrides, "UCS");
    // the check case reads the same overrides: the same rock, another test
    const std::optional<CaseParameters> check =
      o.check_file.empty() ? std::nullopt : std::optional(read_case(o.check_file, o.overrides, "BTS"));
    const double target = o.target > 0 ? o.target : base.rock_case.ucs;
    if (!(target > 0))
      throw InputError("cosim calibrate --simulate: the case's group has no UCS; give --ucs MPa");
    if (!o.bts_file.empty())
    {
      if (check)
        throw InputError("cosim calibrate: --with-bts calibrates on the BTS case; --check is for the UCS-only calibration");
      const CaseParameters disc = read_case(o.bts_file, o.overrides, "BTS");
      require_same_rock(base, disc, o.bts_file);
      return joint_calibration(o, base, disc, target);
    }
    if (o.bts_target > 0)
      throw InputError("cosim calibrate: --bts is the target of --with-bts, --cutoff-from or --mb-from");

    const ScaleFit fit = fit_scale(o, "cohesion_MPa", "mean_UCS_MPa", 3, base.rock.cohesion, target, [&](const double k) {
      return sample(scaled(base, k), o.seeds, "UCS at scale " + std::to_string(k));
    });
    const double  k = fit.k;
    const Sample &s = fit.sample;
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
    if (!fit.converged)
    {
      std::fprintf(stderr, "cosim calibrate --simulate: not converged to %.2f %% in 8 iterations\n",
                   100 * o.tolerance);
      return 1;
    }
    return 0;
  }
} // namespace app
