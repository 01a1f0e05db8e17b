#include <app/case_file.h>
#include <app/cli.h>
#include <diagnose/text_input.h>
#include <diagnose/calibrate.h>
#include <diagnose/csv.h>
#include <diagnose/material_table.h>
#include <app/output_writer.h>
#include <app/paths.h>
#include <coupling/references.h>
#include <coupling/run_case.h>
#include <app/resource_estimate.h>
#include <app/result_folder.h>
#include <app/run_command.h>
#include <app/study.h>

#include "study_jobs.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <thread>

namespace app
{
  using diagnose::trim;
  using diagnose::MaterialGroup;
  using diagnose::MaterialTable;
  using coupling::InputError;
  using coupling::CaseParameters;
  using coupling::Summary;
  using coupling::find_extra;
  using coupling::mohr_coulomb_axial_strength;

  namespace fs = std::filesystem;

  namespace
  {
    constexpr double pi = 3.14159265358979323846;

    /// One swept key and its values, as given.
    struct Dimension
    {
      std::string key; ///< "Section/Key"; "Rock/Group" for --groups
      std::vector<std::string> values;
    };

    struct StudyOptions
    {
      std::string case_file;
      std::string output;
      std::vector<std::string> overrides;
      std::vector<Dimension> vary; ///< first one is the x-axis of the plot
      std::string groups;          ///< "" none, "all", or "M1,M2,..."
      std::optional<double> memory_limit; ///< --memory-limit GIB [bytes]
      bool force = false;
      bool quiet = false;
      int jobs   = 1;             ///< --jobs N: runs side by side as child processes
      bool print_commands = false; ///< --print-commands: one `cosim run` line per run, nothing run
      bool collect        = false; ///< --collect: study.csv from runs already in OUTDIR
    };

    std::vector<std::string> split_list(const std::string &text)
    {
      std::vector<std::string> items;
      std::stringstream in(text);
      std::string item;
      while (std::getline(in, item, ','))
        items.push_back(trim(item));
      return items;
    }

    const char *usage =
      "usage: cosim study CASE.prm --key \"Section/Key\" --values a,b,... [--vary "
      "\"Section/Key=a,b\"] "
      "[--groups M1,M2|all] [-o OUTDIR] [--set \"Section/Key=value\"] [--jobs N | --print-commands | "
      "--collect] [--force] [--quiet]";

    StudyOptions parse_options(const std::vector<std::string> &args)
    {
      StudyOptions o;
      ArgumentCursor cursor("study", args);
      std::string pending_key; // a --key waiting for its --values
      auto add = [&](const std::string &key, const std::string &list, const std::string &option) {
        const std::vector<std::string> values = split_list(list);
        if (values.empty())
          throw InputError("cosim study: " + option + " for '" + diagnose::clip(key) +
                           "' has no values; give comma-separated values, e.g. 0.005,0.004,0.003");
        if (key.empty() || key.find('/') == std::string::npos)
          throw InputError(
            "cosim study: " + option + ": '" + diagnose::clip(key) +
            "' is not a parameter key; write it as \"Section/Key\", e.g. \"SPH/Particle spacing\"");
        for (const auto &v : values)
          if (v.empty())
            throw InputError(
              "cosim study: " + option + " for '" + diagnose::clip(key) + "': '" + diagnose::clip(list) +
              "' has an empty value; give comma-separated values, e.g. 0.005,0.004,0.003");
        for (const auto &d : o.vary)
          if (d.key == key)
            throw InputError("cosim study: key '" + diagnose::clip(key) +
                             "' is varied twice; give all its values in one list");
        o.vary.push_back({key, values});
      };
      while (!cursor.done())
      {
        const std::string a = cursor.next();
        if (a == "-o" || a == "--output")
          o.output = cursor.value(a);
        else if (a == "--set")
          o.overrides.push_back(cursor.value(a));
        else if (a == "--key")
        {
          if (!pending_key.empty())
            throw InputError("cosim study: --key '" + pending_key +
                             "' has no --values before the next --key");
          pending_key = cursor.value(a);
          if (pending_key.empty())
            throw InputError("cosim study: --key needs a \"Section/Key\"");
        }
        else if (a == "--values")
        {
          if (pending_key.empty())
            throw InputError("cosim study: --values without a --key before it; e.g. --key "
                             "\"SPH/CSLH\" --values 1.05,1.2,1.3");
          add(pending_key, cursor.value(a), "--values");
          pending_key.clear();
        }
        else if (a == "--vary")
        {
          const std::string spec = cursor.value(a);
          const auto eq          = spec.find('=');
          if (eq == std::string::npos)
            throw InputError("cosim study: --vary '" + diagnose::clip(spec) +
                             "' has no '='; write \"Section/Key=a,b,c\"");
          add(trim(spec.substr(0, eq)), spec.substr(eq + 1), "--vary");
        }
        else if (a == "--groups")
          o.groups = trim(cursor.value(a));
        else if (a == "--memory-limit")
          o.memory_limit = memory_limit_option(cursor, a);
        else if (a == "--force")
          o.force = true;
        else if (a == "--jobs" || a == "-j")
        {
          const std::string text = cursor.value(a);
          char *end              = nullptr;
          errno                  = 0;
          const long n           = std::strtol(text.c_str(), &end, 10);
          if (text.empty() || *end != '\0' || errno != 0 || n < 1 || n > 1024)
            throw InputError("cosim study: --jobs '" + diagnose::clip(text) +
                             "' is not a number of runs from 1 to 1024");
          o.jobs = static_cast<int>(n);
        }
        else if (a == "--print-commands")
          o.print_commands = true;
        else if (a == "--collect")
          o.collect = true;
        else if (a == "--quiet" || a == "-q")
          o.quiet = true;
        else if (!a.empty() && a[0] == '-')
          throw InputError(
            "cosim study: unknown option '" + diagnose::clip(a) + "'" +
            did_you_mean(a, {"--output", "--set", "--key", "--values", "--vary", "--groups",
                             "--jobs", "--print-commands", "--collect", "--force", "--quiet", "--help"}) +
            "; accepted: -o, --set, --key, --values, --vary, --groups, --jobs, --print-commands, --collect, "
            "--force, --quiet");
        else if (o.case_file.empty())
          o.case_file = a;
        else
          throw InputError("cosim study: a second case file '" + diagnose::clip(a) + "' (after '" + diagnose::clip(o.case_file) +
                           "'); study takes one CASE.prm");
      }
      if (!pending_key.empty())
        throw InputError("cosim study: --key '" + pending_key +
                         "' has no --values; e.g. --values 0.7,0.8,0.9");
      if (o.case_file.empty())
        throw InputError(std::string("cosim study: no case file; ") + usage);
      if (o.vary.empty() && o.groups.empty())
        throw InputError(
          std::string("cosim study: nothing to vary; give --key/--values, --vary or --groups; ") +
          usage);
      if (int(o.jobs > 1) + int(o.print_commands) + int(o.collect) > 1)
        throw InputError("cosim study: --jobs, --print-commands and --collect exclude each other; give one");
      for (const auto &d : o.vary)
        if (d.key == "Rock/Group" && !o.groups.empty())
          throw InputError(
            "cosim study: Rock/Group is varied and --groups is given; use one of them");
      return o;
    }

    /// The "Rock/Data directory" that read_case_file resolved (an absolute path in
    /// used_parameters).
    std::string data_directory_of(const CaseFile &c)
    {
      std::istringstream in(c.used_parameters);
      std::string line;
      while (std::getline(in, line))
      {
        const std::string t = trim(line);
        if (t.rfind("set Data directory", 0) != 0)
          continue;
        const auto eq = t.find('=');
        if (eq == std::string::npos)
          continue;
        std::string value = t.substr(eq + 1);
        const auto hash   = value.find('#');
        if (hash != std::string::npos)
          value = value.substr(0, hash);
        value = trim(value);
        if (!value.empty())
          return value;
      }
      return data_directory().string();
    }

    /// A folder-name-safe spelling of "Key=value": the key's last part, blanks as '_'.
    std::string folder_part(const std::string &key, const std::string &value)
    {
      std::string name = key.substr(key.rfind('/') + 1) + "=" + value;
      for (auto &ch : name)
        if (!(std::isalnum(static_cast<unsigned char>(ch)) || ch == '.' || ch == '-' || ch == '=' ||
              ch == '+'))
          ch = '_';
      return name;
    }

    /// A CSV cell: quoted when it holds a comma or quote.
    std::string cell(const std::string &text)
    {
      if (text.find_first_of(",\"\n") == std::string::npos)
        return text;
      std::string q = "\"";
      for (const char ch : text)
        q += (ch == '"') ? std::string("\"\"") : std::string(1, ch);
      return q + "\"";
    }

    std::string number(const double v, const char *format = "%.6g")
    {
      if (!std::isfinite(v))
        return "";
      char buffer[64];
      std::snprintf(buffer, sizeof buffer, format, v);
      return buffer;
    }

    /// One planned run.
    struct Run
    {
      std::vector<std::string> values;    ///< one per dimension
      std::vector<std::string> overrides; ///< the --set list of its `cosim run`
      std::string folder;
      CaseFile case_file;
      StudyReference reference;
      int status = -1; ///< 0 done, 3 unstable, 4 interrupted, 1 failed (see its .log), -1 not run
      Summary summary;
    };

    StudyReference reference_of(const CaseParameters &p, const MaterialGroup *group)
    {
      StudyReference r;
      const double c = p.rock.cohesion, phi = p.rock.friction_angle * 180.0 / pi; // [deg]
      const double s = std::sin(phi * pi / 180.0), k = std::cos(phi * pi / 180.0);
      // a Hoek-Brown rock's own envelope (intact, s = 1): sigma_ci in uniaxial compression, the
      // disc centre's state (3 t, -t) on it or on the cut-off, sigma1 at the confinement
      std::optional<diagnose::HoekBrownStrength> hb;
      if (p.rock.model == sph::RockModel::hoek_brown)
        hb = diagnose::HoekBrownStrength{p.rock.hb_sigma_ci, p.rock.hb_mb, p.rock.hb_a, p.rock.tensile_strength};
      if (p.test == "BTS")
      {
        r.envelope    = hb ? diagnose::hoek_brown_disc_strength(*hb) : 2 * c * k / (1 + s);
        r.measured    = group ? group->bts : r.envelope;
        r.description = group ? "Table 3 BTS" : "Eq. 15 of the c, phi in use";
      }
      else if (p.test == "CTCS")
      {
        r.envelope = hb ? diagnose::hoek_brown_sigma1(*hb, p.confining_pressure)
                        : mohr_coulomb_axial_strength(c, phi, p.confining_pressure);
        if (group && group->measured_cohesion && group->measured_friction_angle)
        {
          r.measured = mohr_coulomb_axial_strength(
            *group->measured_cohesion, *group->measured_friction_angle, p.confining_pressure);
          r.description = "envelope of Table 3 measured c, phi";
        }
        else
        {
          r.measured    = r.envelope;
          r.description = "envelope of the c, phi in use";
        }
      }
      else
      {
        r.envelope    = hb ? hb->sigma_ci : mohr_coulomb_axial_strength(c, phi, 0.0);
        r.measured    = group ? group->ucs : r.envelope;
        r.description = group ? "Table 3 UCS" : "Eq. 14 of the c, phi in use";
      }
      return r;
    }

    /// Runs tools/plot_study.py; "" on success, else a one-line reason.
    std::string plot_study(const fs::path &csv, const fs::path &png,
                           const std::vector<std::string> &columns)
    {
      std::vector<std::string> args = {csv.string(), png.string()};
      args.insert(args.end(), columns.begin(), columns.end());
      return run_plot_script("plot_study.py", args, png.string());
    }

    std::string status_word(const int status)
    {
      switch (status)
      {
        case 0:
          return "ok";
        case 3:
          return "unstable";
        case 4:
          return "interrupted";
        case 1:
          return "failed";
        default:
          return "not run";
      }
    }

    struct StudyTotals
    {
      std::size_t n_ok = 0;
      double mean_error = 0, max_error = 0; ///< |error| against the references [%]
    };

    /// study.csv and study.png of `runs` into `dir`.
    StudyTotals write_study_table(const fs::path &dir, const std::vector<Dimension> &dims,
                                  const std::vector<Run> &runs)
    {
      // study.csv
      std::ostringstream csv;
      csv << "folder";
      std::vector<std::string> value_columns;
      for (const auto &d : dims)
        value_columns.push_back(d.key);
      for (const auto &c : value_columns)
        csv << "," << cell(c);
      csv << ",test,peak_stress_MPa,reference_MPa,error_percent,envelope_MPa,reference,youngs_"
             "modulus_GPa,"
             "platen_modulus_GPa,poissons_ratio,strain_at_peak,displacement_at_peak_mm,peak_force_"
             "kN,n_particles,"
             "n_steps,wall_seconds,max_kinetic_to_internal_energy,max_force_imbalance,quasi_static,"
             "stop_reason,"
             "status";
      // the test's own results (summary.json's further entries: failure pattern, cutting
      // forces), named as the first finished run names them
      std::vector<std::string> extra_columns;
      for (const auto &run : runs)
        if (run.status == 0)
        {
          for (const auto &[name, value] : run.summary.extra)
            extra_columns.push_back(name);
          break;
        }
      for (const auto &c : extra_columns)
        csv << "," << cell(c);
      csv << "\n";
      double sum_error = 0, max_error = 0;
      std::size_t n_ok = 0;
      for (const auto &run : runs)
      {
        const Summary &s        = run.summary;
        const CaseParameters &p = run.case_file.parameters;
        csv << cell(run.folder);
        for (const auto &v : run.values)
          csv << "," << cell(v);
        csv << "," << p.test;
        if (run.status == 0)
        {
          const double error = 100 * (s.peak_stress / run.reference.measured - 1);
          sum_error += std::abs(error), max_error = std::max(max_error, std::abs(error)), ++n_ok;
          const double gauge = p.test == "BTS" ? p.diameter : p.length;
          csv << "," << number(s.peak_stress * 1e-6) << "," << number(run.reference.measured * 1e-6)
              << "," << number(error, "%.3f") << "," << number(run.reference.envelope * 1e-6) << ","
              << cell(run.reference.description) << ","
              << (s.youngs_modulus > 0 ? number(s.youngs_modulus * 1e-9) : "") << ","
              << number(s.platen_modulus * 1e-9) << ","
              << (s.poissons_ratio < 0 ? "" : number(s.poissons_ratio)) << ","
              << number(s.strain_at_peak) << "," << number(s.strain_at_peak * gauge * 1e3) << ","
              << number(s.peak_force * 1e-3) << "," << s.n_particles << "," << s.n_steps << ","
              << number(s.wall_seconds, "%.2f") << "," << number(s.max_kinetic_to_internal_energy)
              << "," << number(s.max_force_imbalance) << "," << (s.quasi_static ? "true" : "false")
              << "," << cell(s.stop_reason) << ",ok";
        }
        else
          csv << ",," << number(run.reference.measured * 1e-6) << ",,"
              << number(run.reference.envelope * 1e-6) << "," << cell(run.reference.description)
              << ",,,,,,,,,,,,,,"
              << status_word(run.status);
        for (const auto &c : extra_columns)
        {
          csv << ",";
          if (run.status == 0)
            if (const auto value = find_extra(s, c))
              csv << number(*value);
        }
        csv << "\n";
      }
      {
        // whole or not at all: a study.csv in OUTDIR is never half-written
          const fs::path partial = dir / ".study.csv.partial";
          write_text_file(partial.string(), csv.str());
          fs::rename(partial, dir / "study.csv");
        }
      std::vector<std::string> plot_columns;
      plot_columns.push_back(value_columns.back()); // x-axis
      plot_columns.insert(plot_columns.end(), value_columns.begin(), value_columns.end() - 1);
      const std::string why =
        plot_study(dir / "study.csv", dir / "study.png", plot_columns);
      if (!why.empty())
        std::fprintf(stderr, "cosim: warning: %s\n", why.c_str());
      return {n_ok, n_ok > 0 ? sum_error / n_ok : 0.0, max_error};
    }

    /// A case file's text without its comment lines (the version and commit lines among them).
    std::string without_comments(const std::string &text)
    {
      std::istringstream in(text);
      std::string line, out;
      while (std::getline(in, line))
        if (trim(line).rfind('#', 0) != 0)
          out += line + "\n";
      return out;
    }

    /// --collect: study.csv and study.png from the runs already in OUTDIR (the commands of
    /// --print-commands, run elsewhere). Each run's used_parameters.prm must be the one this study
    /// plans for its folder.
    int collect_study(const std::string &output, const std::vector<Dimension> &dims, std::vector<Run> &runs,
                      const bool quiet)
    {
      const fs::path dir = fs::absolute(output).lexically_normal();
      std::error_code ec;
      if (!fs::is_directory(dir, ec))
        throw InputError("cosim study --collect: " + diagnose::clip(dir.string()) +
                         " is not a folder; run the commands of --print-commands into it first");
      std::size_t n_unstable = 0, n_unfinished = 0;
      for (auto &run : runs)
      {
        const fs::path done = dir / run.folder;
        fs::path failed     = done;
        failed += ".failed";
        const fs::path folder = fs::exists(done / "summary.json", ec) ? done : failed;
        if (!fs::exists(folder / "summary.json", ec))
        {
          run.status = -1;
          ++n_unfinished;
          continue;
        }
        std::ifstream in(folder / "used_parameters.prm", std::ios::binary);
        std::ostringstream used;
        used << in.rdbuf();
        if (without_comments(used.str()) != without_comments(run.case_file.used_parameters))
          throw InputError("cosim study --collect: " + diagnose::clip((folder / "used_parameters.prm").string()) +
                           " is not the case this study plans for " + run.folder +
                           " (other parameters, case file or options)");
        const SummaryFile file = read_summary_json((folder / "summary.json").string());
        if (file.summary)
          run.status = 0, run.summary = *file.summary;
        else if (file.status == "unstable")
          run.status = 3, ++n_unstable;
        else
          run.status = file.status == "interrupted" ? 4 : 1, ++n_unfinished;
      }
      const StudyTotals totals = write_study_table(dir, dims, runs);
      if (!quiet)
        std::fprintf(stderr,
                     "cosim study: collected %zu of %zu runs (%zu unstable, %zu not finished), mean |error| "
                     "%.2f %%, max |error| %.2f %% -> %s\n",
                     totals.n_ok, runs.size(), n_unstable, n_unfinished, totals.mean_error, totals.max_error,
                     diagnose::clip((dir / "study.csv").string()).c_str());
      return n_unfinished > 0 ? 4 : n_unstable > 0 ? 3 : 0;
    }

    /// The `cosim run` of one planned run (absolute paths: a batch job may start elsewhere).
    RunCommand run_command(const StudyOptions &options, const Run &run, const fs::path &folder,
                           const std::optional<double> &memory_limit)
    {
      RunCommand c;
      c.folder = folder;
      c.argv   = {executable_path().string(), "run", fs::absolute(options.case_file).lexically_normal().string()};
      for (const auto &o : run.overrides)
        c.argv.insert(c.argv.end(), {"--set", o});
      c.argv.insert(c.argv.end(), {"-o", folder.string(), "--quiet"});
      if (memory_limit)
      {
        char gib[32];
        std::snprintf(gib, sizeof gib, "%.6g", *memory_limit / (1024.0 * 1024.0 * 1024.0));
        c.argv.insert(c.argv.end(), {"--memory-limit", gib});
      }
      return c;
    }
  } // namespace

  std::string study_help()
  {
    return std::string(usage) +
           "\n"
           "\n"
           "Runs one case for every combination of the varied parameters (and rock groups), each "
           "as\n"
           "`cosim run` into a subfolder of OUTDIR (default results/study-<case stem>), one after "
           "the\n"
           "other, and writes:\n"
           "  study.csv   one row per run: folder, the varied values, test, peak_stress_MPa,\n"
           "              reference_MPa (Table 3 UCS / BTS of the group; CTCS: the Mohr-Coulomb "
           "envelope\n"
           "              of Table 3's measured c, phi where the group has them, else of the c, "
           "phi in\n"
           "              use), error_percent, envelope_MPa (closed form of the c, phi in use;\n"
           "              Hoek-Brown: its envelope's),\n"
           "              youngs_modulus_GPa, platen_modulus_GPa, poissons_ratio, strain_at_peak,\n"
           "              displacement_at_peak_mm, n_particles, n_steps, wall_seconds,\n"
           "              max_kinetic_to_internal_energy, max_force_imbalance, quasi_static,\n"
           "              stop_reason, status (ok / unstable), then the test's further results\n"
           "              as summary.json names them (failure pattern: failure_onset_*,\n"
           "              damaged_volume_fraction, crack_alignment; cutting forces)\n"
           "  study.png   peak stress against the first varied key (one line per combination of "
           "the\n"
           "              others), and every run's curve (tools/plot_study.py)\n"
           "  <run>/      each run's own result folder (summary.json, history.csv, ...)\n"
           "\n"
           "options:\n"
           "  --key \"S/K\" --values a,b,...  one varied key and its values (repeatable pair)\n"
           "  --vary \"S/K=a,b,...\"          the same in one argument (repeatable); all keys "
           "combine\n"
           "  --groups M1,M2,...|all        also vary Rock/Group (all: every group of the data "
           "folder)\n"
           "  -o, --output OUTDIR           result folder; never replaced without --force\n"
           "  --set \"S/K=value\"             a fixed override for every run (repeatable)\n"
           "  --force                       replace an existing OUTDIR written by cosim (only once the "
           "study has ended)\n"
           "  --memory-limit GIB            memory a run may use (default 90 % of the available memory)\n"
           "  -j, --jobs N                  run N cases side by side, each a `cosim run` child process\n"
           "                                with 1/N of the cores (OMP_NUM_THREADS) and of the memory\n"
           "  --print-commands              print one `cosim run` command per case (absolute paths,\n"
           "                                results into OUTDIR/<run>) and run nothing: for a batch\n"
           "                                system (cases/studies/slurm/); then --collect\n"
           "  --collect                     write study.csv and study.png into OUTDIR from the runs\n"
           "                                found there (each checked against the case it should be);\n"
           "                                exit 4 while some are missing\n"
           "  -q, --quiet                   no line per run\n"
           "\n"
           "Every combination is read and checked before the first run: a bad key or value stops "
           "the\n"
           "study with one line and nothing written. The study is written into a hidden sibling "
           "folder\n"
           "and renamed to OUTDIR at the end. Example (the paper's Fig. 13 on the BTS):\n"
           "  cosim study cases/bts/bts.prm --key \"SPH/CSLH\" --values 1.05,1.2,1.3 -o "
           "results/bts-cslh\n"
           "\n"
           "SIGINT / SIGTERM / SIGHUP: the run in progress stops with its checkpoint, the study "
           "stops after it and\n"
           "writes study.csv (status interrupted / not run) into OUTDIR (OUTDIR.interrupted when "
           "OUTDIR exists).\n"
           "\n"
           "Exit status: 0 done, 2 bad input, 3 some runs unstable (marked in study.csv), 4 "
           "interrupted, 1 other failure.\n";
  }

  int study_main(const std::vector<std::string> &args)
  {
    const StudyOptions options = parse_options(args);
    const std::string stem     = fs::path(options.case_file).stem().string();
    const CaseFile base        = read_case_file(options.case_file, options.overrides);
    const MaterialTable table  = MaterialTable::read(data_directory_of(base));

    std::vector<Dimension> dims; // series dimensions first, the x-axis last (fastest)
    if (!options.groups.empty())
    {
      Dimension g{"Rock/Group", {}};
      if (options.groups == "all")
        for (const auto &m : table.groups())
          g.values.push_back(m.group);
      else
        g.values = split_list(options.groups);
      if (g.values.empty())
        throw InputError("cosim study: --groups has no names; e.g. M1,M2 or all");
      for (const auto &v : g.values)
        if (v.empty())
          throw InputError("cosim study: --groups '" + diagnose::clip(options.groups) +
                           "' has an empty name; e.g. M1,M2 or all");
      dims.push_back(g);
    }
    for (std::size_t i = 1; i < options.vary.size(); ++i)
      dims.push_back(options.vary[i]);
    if (!options.vary.empty())
      dims.push_back(options.vary.front());

    // side by side, the runs share the memory: each may use its share of the limit
    std::optional<double> run_limit = options.memory_limit;
    if (options.jobs > 1)
    {
      if (!run_limit)
        if (const auto available = available_memory())
          run_limit = 0.9 * *available;
      if (run_limit)
        *run_limit /= options.jobs;
    }

    // every combination, read and checked before anything is written
    std::vector<Run> runs;
    std::vector<std::size_t> index(dims.size(), 0);
    for (bool more = true; more;)
    {
      Run run;
      std::vector<std::string> overrides = options.overrides;
      std::string folder;
      for (std::size_t d = 0; d < dims.size(); ++d)
      {
        run.values.push_back(dims[d].values[index[d]]);
        overrides.push_back(dims[d].key + "=" + run.values.back());
        folder += (folder.empty() ? "" : "_") + folder_part(dims[d].key, run.values.back());
      }
      char prefix[16];
      std::snprintf(prefix, sizeof prefix, "%02zu-", runs.size() + 1);
      run.folder    = prefix + folder;
      run.overrides = overrides;
      run.case_file = read_case_file(options.case_file, overrides);
      check_case_resources(run.case_file, run_limit);
      run.reference =
        reference_of(run.case_file.parameters, table.lookup(run.case_file.parameters.rock_case.group));
      runs.push_back(std::move(run));
      more = false;
      for (std::size_t d = dims.size(); d-- > 0;)
      {
        if (++index[d] < dims[d].values.size())
        {
          more = true;
          break;
        }
        index[d] = 0;
      }
    }
    const std::string output = options.output.empty() ? "results/study-" + stem : options.output;
    for (const auto &w : base.warnings)
      std::fprintf(stderr, "cosim: warning: %s\n", w.c_str());

    if (options.print_commands)
    {
      // one line per run for a batch system; nothing is run or written
      const fs::path outdir = fs::absolute(output).lexically_normal();
      for (const auto &run : runs)
        std::printf("%s\n", command_line(run_command(options, run, outdir / run.folder, {}).argv).c_str());
      return 0;
    }
    if (options.collect)
      return collect_study(output, dims, runs, options.quiet);

    const fs::path target = check_result_folder(output, options.force,
                                                {fs::path(options.case_file), fs::path(data_directory_of(base))});

    // Everything checked: write into the staging folder only. A signal stops the run in progress
    // (its checkpoint kept in the study folder) and the study after it.
    const StopSignals stop_signals;
    ResultFolder folder(target, "study");
    const fs::path &staging = folder.staging();
    auto describe = [&](const Run &run) {
      std::string what;
      for (std::size_t d = 0; d < dims.size(); ++d)
        what += (what.empty() ? "" : ", ") + dims[d].key + "=" + run.values[d];
      return what;
    };
    auto report = [&](const std::size_t i) {
      const Run &run = runs[i];
      if (options.quiet)
        return;
      if (run.status == 0)
        std::fprintf(stderr,
                     "cosim study: [%zu/%zu] %s: peak %.2f MPa (%+.2f %% against %.2f, %s), "
                     "%zu steps, %.1f s\n",
                     i + 1, runs.size(), describe(run).c_str(), run.summary.peak_stress * 1e-6,
                     100 * (run.summary.peak_stress / run.reference.measured - 1),
                     run.reference.measured * 1e-6, run.reference.description.c_str(),
                     run.summary.n_steps, run.summary.wall_seconds);
      else if (run.status == 3)
        std::fprintf(stderr, "cosim study: [%zu/%zu] %s: unstable (see %s.failed)\n", i + 1, runs.size(),
                     describe(run).c_str(), diagnose::clip((target / run.folder).string()).c_str());
      else if (run.status == 1)
        std::fprintf(stderr, "cosim study: [%zu/%zu] %s: failed (see %s.log)\n", i + 1, runs.size(),
                     describe(run).c_str(), diagnose::clip((target / run.folder).string()).c_str());
    };
    {
      bool any_unstable = false, any_failed = false;
      std::vector<std::size_t> interrupted; // runs stopped with a checkpoint
      if (options.jobs == 1)
        for (std::size_t i = 0; i < runs.size(); ++i)
        {
          Run &run = runs[i];
          if (StopSignals::received() != 0)
            break; // stopped between runs: the rest are not run
          fs::path interrupted_folder;
          run.status = run_into_folder(run.case_file, staging / run.folder, false, true, &run.summary, "",
                                       &interrupted_folder);
          if (run.status == 4)
          {
            interrupted.push_back(i);
            break;
          }
          report(i);
        }
      else
      {
        // side by side: each run a `cosim run` child with its share of the cores, its summary
        // read back from its folder
        std::vector<RunCommand> commands;
        for (const auto &run : runs)
          commands.push_back(run_command(options, run, staging / run.folder, run_limit));
        const int cores   = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
        const int threads = std::max(1, cores / options.jobs);
        run_side_by_side(commands, options.jobs, threads, [&](const std::size_t i, const int status) {
          Run &run                = runs[i];
          const fs::path run_path = staging / run.folder;
          const fs::path log      = run_path.string() + ".log";
          run.status              = status == 0 || status == 3 || status == 4 ? status : 1;
          if (status == 0)
          {
            try
            {
              const SummaryFile file = read_summary_json((run_path / "summary.json").string());
              if (file.summary)
                run.summary = *file.summary;
              else
                run.status = 1;
            }
            catch (const InputError &)
            {
              run.status = 1;
            }
          }
          if (run.status == 4)
            interrupted.push_back(i);
          std::error_code ignored;
          if (run.status != 1)
            fs::remove(log, ignored); // a failed run keeps its log beside its folder
          report(i);
        });
        std::sort(interrupted.begin(), interrupted.end());
      }
      for (const auto &run : runs)
        any_unstable = any_unstable || run.status == 3, any_failed = any_failed || run.status == 1;

      const StudyTotals totals = write_study_table(staging, dims, runs);
      if (!interrupted.empty() || StopSignals::received() != 0)
      {
        // never replaces a result: OUTDIR when free, else OUTDIR.interrupted
        std::error_code ec;
        fs::path destination = target;
        if (fs::exists(fs::symlink_status(target, ec)))
          destination += ".interrupted";
        const fs::path published = folder.publish(ResultStatus::interrupted,
                                                  result_status(destination) == ResultStatus::interrupted,
                                                  destination);
        std::size_t n_done = 0;
        for (const auto &run : runs)
          n_done += run.status == 0 || run.status == 3;
        std::string how;
        if (!interrupted.empty())
          how = "; continue run " + runs[interrupted.front()].folder + " with: cosim run --restart " +
                shell_word((published / runs[interrupted.front()].folder).string()) +
                (interrupted.size() > 1 ? " (and likewise the other " + std::to_string(interrupted.size() - 1) +
                                            " interrupted runs)"
                                        : std::string());
        std::fprintf(stderr, "cosim study: interrupted by a signal after %zu of %zu runs; study.csv and the runs "
                     "are in %s%s\n", n_done, runs.size(), diagnose::clip(published.string()).c_str(), how.c_str());
        return 4;
      }
      const fs::path published = folder.publish(ResultStatus::complete, options.force);
      if (!options.quiet && totals.n_ok > 0)
        std::fprintf(stderr,
                     "cosim study: %zu runs, mean |error| %.2f %%, max |error| %.2f %% -> %s\n",
                     runs.size(), totals.mean_error, totals.max_error, diagnose::clip(published.string()).c_str());
      return any_failed ? 1 : any_unstable ? 3 : 0;
    }
  }
} // namespace app
