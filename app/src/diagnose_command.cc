// `cosim diagnose DATA_DIR`: options, then the diagnosis (diagnose/), its files and plots.
#include <app/cli.h>
#include <diagnose/text_input.h>
#include <app/diagnose_command.h>
#include <app/output_writer.h>
#include <app/resource_estimate.h>
#include <app/result_folder.h>
#include <coupling/errors.h>
#include <diagnose/csv.h>
#include <diagnose/diagnose.h>

#include <app/case_file.h>

#include <algorithm>
#include <cmath>
#include <optional>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <unistd.h>

namespace app
{

  namespace fs = std::filesystem;
  using coupling::InputError;
  using diagnose::parse_finite_double;

  std::string diagnose_help()
  {
    return "usage: cosim diagnose DATA_DIR [-o OUTDIR] [--force] [--bic-threshold X] [--coupled-spacing DX]\n"
           "                      [--simulations N]\n"
           "\n"
           "What the simulation gets wrong on measured data, the cause, the extension and the "
           "gain.\n"
           "DATA_DIR: any of material.csv, strength.csv, curves/*.csv (docs/design.md, 'Measured "
           "data').\n"
           "The baseline is linear Mohr-Coulomb with the measured c, phi (or calibrated from UCS "
           "and BTS),\n"
           "measured E, rigid frictionless platens and the displacement read at the platen. Each "
           "candidate\n"
           "(tension_cutoff, envelope_curvature, crack_closure, machine_compliance, end_friction,\n"
           "heterogeneity, loading_rate) is fitted with PETSc TAO (POUNDERS) on a material-point "
           "surrogate\n"
           "and judged by BIC and leave-one-specimen-out error.\n"
           "\n"
           "writes into OUTDIR (default results/diagnose):\n"
           "  diagnosis.json  identified, candidates, baseline, extended, gain\n"
           "  report.md       candidates table, named cause and evidence, fitted values, gain\n"
           "  envelope.csv, points.csv, envelope.png, curves.png\n"
           "  with --coupled-spacing: coupled_gain and simulations in diagnosis.json,\n"
           "  simulations.png, simulations/ (s<i>_baseline.prm, s<i>_extended.prm, curves.csv);\n"
           "  a specimen whose run goes unstable is reported (stop_reason, unstable) and left\n"
           "  out of coupled_gain, with a warning on stderr\n"
           "\n"
           "options:\n"
           "  -o, --output OUTDIR  result folder; never replaced without --force\n"
           "  --force              replace an existing OUTDIR written by cosim\n"
           "  --memory-limit GIB   memory a coupled run may use (default 90 % of the available memory)\n"
           "  --bic-threshold X    Delta BIC an effect must earn (default 10)\n"
           "  --coupled-spacing DX also run the coupled simulator (spacing DX [m]; 0.0025: the\n"
           "                       default cases') on held-out specimens with the baseline and\n"
           "                       the extended case: those the baseline misses by more than 3\n"
           "                       noise SDs (curves; strength rows of the group it misses most),\n"
           "                       worst first, and every BTS curve (its displacement) after them\n"
           "                       (simulations/: the case files and curves; tens of s a run)\n"
           "  --simulations N      specimens the coupled simulator runs, at most (default 6)\n";
  }

  diagnose::CaseReader case_reader(const std::string &defaults)
  {
    return [defaults](const std::vector<std::string> &overrides, coupling::CaseParameters &parameters,
                      std::string &text) {
      std::vector<std::string> named = {"Test/Name=diagnose"};
      named.insert(named.end(), overrides.begin(), overrides.end());
      CaseFile c = read_case_file(defaults, named);
      parameters = c.parameters;
      text       = c.used_parameters;
      const std::string at = " (" + defaults + ")";
      if (const auto i = text.find(at); i != std::string::npos)
        text.replace(i, at.size(), " (written by cosim diagnose)");
      // the rock is set by explicit keys, not looked up in a group's tables
      const std::string from = "# Rock values resolved from group ";
      if (const auto i = text.find(from); i != std::string::npos)
        text.replace(i, text.find('\n', i) - i, "# Rock values: the explicit keys below (Rock/Group is the default's, unused for them)");
    };
  }

  namespace
  {
    /// An empty case file (every key at its default) for the cases of the coupled runs, removed
    /// when the diagnosis ends.
    class DefaultCase
    {
    public:
      DefaultCase()
          : path_(fs::temp_directory_path() / ("cosim-diagnose-" + std::to_string(::getpid()) + ".prm"))
      {
        std::ofstream o(path_);
        o << "# the defaults; cosim diagnose sets the specimen, the rock and the effects\n";
        if (!o)
          throw std::runtime_error("cosim diagnose: cannot write " + path_.string());
      }
      ~DefaultCase()
      {
        std::error_code ec;
        fs::remove(path_, ec);
      }
      DefaultCase(const DefaultCase &)            = delete;
      DefaultCase &operator=(const DefaultCase &) = delete;
      diagnose::CaseReader reader() const { return case_reader(path_.string()); }

    private:
      fs::path path_;
    };
  } // namespace

  int diagnose_main(const std::vector<std::string> &args)
  {
    std::string data_dir, out_dir = "results/diagnose";
    bool force = false;
    std::optional<double> memory_limit;
    diagnose::Options options;
    for (std::size_t i = 0; i < args.size(); ++i)
    {
      const std::string &a = args[i];
      const auto next      = [&]() -> std::string {
        if (i + 1 >= args.size())
          throw InputError("cosim diagnose: " + a + " needs a value");
        if (diagnose::trim(args[i + 1]).empty())
          throw InputError("cosim diagnose: option " + a + " has an empty value (see cosim diagnose --help)");
        return args[++i];
      };
      if (a == "-o" || a == "--output")
        out_dir = next();
      else if (a == "--force")
        force = true;
      else if (a == "--memory-limit")
      {
        const auto v = parse_finite_double(next());
        if (!v || !(*v > 0 && *v < 1e6))
          throw InputError("cosim diagnose: --memory-limit takes the memory a coupled run may use in GiB, a number > 0");
        memory_limit = *v * 1024.0 * 1024.0 * 1024.0;
      }
      else if (a == "--bic-threshold")
      {
        const auto v = parse_finite_double(next());
        if (!v || *v < 0)
          throw InputError("cosim diagnose: --bic-threshold takes a non-negative number");
        options.bic_threshold = *v;
      }
      else if (a == "--coupled-spacing")
      {
        const auto v = parse_finite_double(next());
        if (!v || !(*v > 0 && *v < 0.01))
          throw InputError(
            "cosim diagnose: --coupled-spacing takes a particle spacing in m, 0 < dx < 0.01");
        options.coupled_spacing = *v;
      }
      else if (a == "--simulations")
      {
        const auto v = parse_finite_double(next());
        if (!v || !(*v >= 1 && *v <= 100) || *v != std::floor(*v))
          throw InputError("cosim diagnose: --simulations takes a whole number of specimens in [1, 100]");
        options.max_simulations = static_cast<int>(*v);
      }
      else if (!a.empty() && a[0] == '-')
        throw InputError("cosim diagnose: unknown option '" + diagnose::clip(a) + "'" +
                         did_you_mean(a, {"--output", "--force", "--bic-threshold",
                                          "--coupled-spacing", "--simulations", "--memory-limit", "--help"}) +
                         "; accepted: -o OUTDIR, --force, --bic-threshold X, --coupled-spacing DX, --simulations N, "
                         "--memory-limit GIB");
      else if (data_dir.empty())
        data_dir = a;
      else
        throw InputError("cosim diagnose: one DATA_DIR only (got '" + diagnose::clip(data_dir) + "' and '" +
                         diagnose::clip(a) + "')");
    }
    if (data_dir.empty())
      throw InputError(
        "cosim diagnose: give the measured-data folder: cosim diagnose DATA_DIR [-o OUTDIR]");
    const fs::path target = check_result_folder(out_dir, force, {fs::path(data_dir)});
    const diagnose::Data data = diagnose::read_data(data_dir);
    if (options.coupled_spacing > 0)
    {
      // the coupled runs model the largest specimen of the curves (a 50 x 100 mm core without)
      double volume = 3.14159265358979 / 4 * 0.05 * 0.05 * 0.1;
      for (const auto &c : data.curves)
        volume = std::max(volume, 3.14159265358979 / 4 * c.diameter * c.diameter * c.length * 1e-9);
      char what[64];
      std::snprintf(what, sizeof what, "--coupled-spacing %g m", options.coupled_spacing);
      check_resources(estimate_for_volume(volume, options.coupled_spacing), what, memory_limit,
                      "--memory-limit GIB");
    }
    std::optional<DefaultCase> default_case;
    if (options.coupled_spacing > 0)
    {
      default_case.emplace();
      options.read_case = default_case->reader();
    }
    const diagnose::Diagnosis d = diagnose::diagnose(data, options);
    ResultFolder folder(target, "diagnose");
    const fs::path out = folder.staging();
    diagnose::write_report(out, d, data_dir);
    const std::string why = run_plot_script("plot_diagnosis.py", {out.string()}, (out / "envelope.png").string());
    if (!why.empty())
      std::fprintf(stderr, "cosim diagnose: plots skipped: %s\n", why.c_str());
    const fs::path published = folder.publish(ResultStatus::complete, force);
    std::string ids;
    for (const auto &i : d.identified)
      ids += (ids.empty() ? "" : ", ") + i;
    if (d.simulations.empty())
      std::printf("identified: %s; gain %.3g (held-out %.3g); wrote %s\n", ids.c_str(), d.gain,
                  d.heldout_gain, diagnose::clip(published.string()).c_str());
    else
      std::printf("identified: %s; gain %.3g (held-out %.3g; coupled simulator, held-out %.3g); wrote %s\n",
                  ids.c_str(), d.gain, d.heldout_gain, d.coupled_gain,
                  diagnose::clip(published.string()).c_str());
    if (const int unstable = diagnose::coupled_unstable(d); unstable > 0)
      std::fprintf(stderr,
                   "cosim diagnose: warning: %d of %zu simulated specimens left out of the "
                   "coupled gain, a run unstable (report.md, Notes)\n",
                   unstable, d.simulations.size());
    return 0;
  }
} // namespace app
