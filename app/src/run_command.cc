#include <app/case_file.h>
#include <app/checkpoint.h>
#include <app/cli.h>
#include <app/output_writer.h>
#include <app/progress.h>
#include <app/paths.h>
#include <app/resource_estimate.h>
#include <app/result_folder.h>
#include <diagnose/csv.h>
#include <diagnose/text_input.h>
#include <app/run_command.h>
#include <coupling/run_case.h>
#include <diagnose/material_table.h>

#include <mpi.h>

#include <cctype>
#include <chrono>
#include <cstring>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>
#include <unistd.h>

namespace app
{
  using coupling::InputError;
  using coupling::InstabilityError;
  using coupling::RunInterrupted;
  using coupling::Summary;
  using coupling::HistoryRow;
  using coupling::RunObserver;
  using coupling::StateArrays;
  using coupling::ParticleSnapshot;
  using coupling::MeshSnapshot;
  using coupling::run_case;
  using coupling::find_extra;

  namespace fs = std::filesystem;
  using diagnose::clip;

  namespace
  {
    /// Set by SIGINT / SIGTERM / SIGHUP, polled by the time loop once per step
    /// (async-signal-safe).
    volatile std::sig_atomic_t stop_signal = 0;
    int stop_signals_depth                 = 0;

    extern "C" void on_stop_signal(int signal)
    {
      stop_signal = signal;
    }
  } // namespace

  StopSignals::StopSignals()
  {
    if (stop_signals_depth++ > 0)
      return; // an outer command (a study) already handles them
    stop_signal = 0;
    struct sigaction sa = {};
    sa.sa_handler       = on_stop_signal;
    sigemptyset(&sa.sa_mask);
    sa.sa_flags = SA_RESETHAND;
    sigaction(SIGINT, &sa, &old_int_);
    sigaction(SIGTERM, &sa, &old_term_);
    sigaction(SIGHUP, &sa, &old_hup_);
  }

  StopSignals::~StopSignals()
  {
    if (--stop_signals_depth > 0)
      return;
    sigaction(SIGINT, &old_int_, nullptr);
    sigaction(SIGTERM, &old_term_, nullptr);
    sigaction(SIGHUP, &old_hup_, nullptr);
  }

  int StopSignals::received()
  {
    return stop_signal;
  }

  namespace
  {
    /// The folder of measured-data tables a case read: Rock/Data directory, else the shipped one.
    std::string data_directory_of(const CaseFile &case_file)
    {
      const std::string &own = case_file.parameters.rock_case.data_directory;
      return own.empty() ? data_directory().string() : own;
    }

    /// What curve.png shows beside the curve: the rock group, the particle spacing and the
    /// group's measured values (Table 3) that the test measures: UCS and E for UCS, BTS for BTS.
    CurveLabels curve_labels(const CaseFile &case_file)
    {
      const coupling::CaseParameters &p = case_file.parameters;
      CurveLabels labels;
      labels.group            = p.rock_case.group;
      labels.particle_spacing = p.sph.spacing;
      if (p.test != "UCS" && p.test != "BTS")
        return labels;
      try
      {
        const diagnose::MaterialTable table = diagnose::MaterialTable::read(data_directory_of(case_file));
        if (const diagnose::MaterialGroup *group = table.lookup(p.rock_case.group))
        {
          labels.source = "Table 3";
          if (p.test == "UCS")
          {
            labels.measured_ucs            = group->ucs;
            labels.measured_youngs_modulus = group->youngs_modulus;
          }
          else
            labels.measured_bts = group->bts;
        }
      }
      catch (const std::exception &)
      {
        // the case was read from these tables, so this does not happen; the plot goes without
      }
      return labels;
    }

    /// Keeps the history in memory, streams snapshots into results.h5, shows progress, writes
    /// checkpoints and the last good state into the staging folder.
    class RecordingObserver : public RunObserver
    {
    public:
      RecordingObserver(ResultsFile &results, ProgressDisplay &progress, const fs::path &folder,
                        const std::string &used_parameters)
        : results_(results)
        , progress_(progress)
        , folder_(folder)
        , used_parameters_(used_parameters)
      {}

      bool stop_requested() override { return StopSignals::received() != 0; }
      void checkpoint(std::size_t step, const StateArrays &state, const coupling::StateRows *rows) override
      {
        write_checkpoint((folder_ / "checkpoint.h5").string(), state, used_parameters_, rows);
        checkpoint_step = static_cast<long>(step);
      }
      void last_good_state(std::size_t step, double time, const ParticleSnapshot &particles) override
      {
        ResultsFile good((folder_ / "last_good_state.h5").string());
        good.add_snapshot(time, particles, {});
        good.close((folder_ / "last_good_state.xdmf").string());
        good_step = static_cast<long>(step);
        good_time = time;
      }

      long checkpoint_step = -1, good_step = -1;
      double good_time = 0;

      void progress(std::size_t step, double time, double fraction) override
      {
        progress_.update(step, time, fraction);
      }
      void history(const HistoryRow &row) override { rows.push_back(row); }
      void snapshot(double time, const ParticleSnapshot &particles, const std::vector<MeshSnapshot> &meshes) override
      {
        results_.add_snapshot(time, particles, meshes);
      }

      std::vector<HistoryRow> rows;

    private:
      ResultsFile &results_;
      ProgressDisplay &progress_;
      fs::path folder_;
      std::string used_parameters_;
    };

    struct RunOptions
    {
      std::string case_file;
      std::string output;
      std::vector<std::string> overrides;
      std::string restart; ///< --restart DIR
      std::optional<double> memory_limit; ///< --memory-limit GIB [bytes]
      bool force = false;
      bool quiet = false;
      bool print_parameters = false; ///< --print-parameters: print the default case file, run nothing
    };

    RunOptions parse_options(const std::vector<std::string> &args)
    {
      RunOptions o;
      ArgumentCursor cursor("run", args);
      while (!cursor.done())
      {
        const std::string a = cursor.next();
        if (a == "-o" || a == "--output")
          o.output = cursor.value(a);
        else if (a == "--set")
          o.overrides.push_back(cursor.value(a));
        else if (a == "--restart")
          o.restart = cursor.value(a);
        else if (a == "--memory-limit")
          o.memory_limit = memory_limit_option(cursor, a);
        else if (a == "--force")
          o.force = true;
        else if (a == "--quiet" || a == "-q")
          o.quiet = true;
        else if (a == "--print-parameters")
          o.print_parameters = true;
        else if (!a.empty() && a[0] == '-')
          throw InputError("cosim run: unknown option '" + diagnose::clip(a) + "'" +
                           did_you_mean(a, {"--output", "--set", "--restart", "--memory-limit", "--force", "--quiet",
                                            "--print-parameters", "--help"}) +
                           "; accepted: -o OUTDIR, --set \"Section/Key=value\", --restart DIR, --memory-limit GIB, "
                           "--force, --quiet, --print-parameters");
        else if (o.case_file.empty())
          o.case_file = a;
        else
          throw InputError("cosim run: a second case file '" + clip(a) + "' (after '" + clip(o.case_file) +
                           "'); run takes one CASE.prm");
      }
      if (o.print_parameters)
        return o;
      if (!o.restart.empty())
      {
        if (!o.case_file.empty() || !o.overrides.empty())
          throw InputError("cosim run --restart " + clip(o.restart) +
                           ": takes no case file and no --set (the run continues with the "
                           "parameters in " + clip(o.restart) + "/used_parameters.prm)");
        o.case_file = (fs::path(o.restart) / "used_parameters.prm").string();
        if (!fs::is_regular_file(o.case_file))
          throw InputError("cosim run --restart " + clip(o.restart) + ": no used_parameters.prm there; "
                           "give the output folder of an interrupted run");
        return o;
      }
      if (o.case_file.empty())
        throw InputError("cosim run: no case file; usage: cosim run CASE.prm [-o OUTDIR] [--set \"Section/Key=value\"]");
      return o;
    }

  } // namespace

  std::optional<double> memory_limit_option(ArgumentCursor &cursor, const std::string &option)
  {
    const double gib = cursor.number(option);
    if (!(gib > 0 && gib < 1e6))
      throw InputError(option + " takes the memory a run may use in GiB, a number > 0 (e.g. " + option + " 64)");
    return gib * 1024.0 * 1024.0 * 1024.0;
  }

  void check_case_resources(const CaseFile &case_file, const std::optional<double> &memory_limit)
  {
    char spacing[32];
    std::snprintf(spacing, sizeof spacing, "%g", case_file.parameters.sph.spacing);
    check_resources(estimate_resources(case_file.parameters),
                    "SPH/Particle spacing = " + std::string(spacing) + " m (" + clip(case_file.parameters.name, 60) + ")",
                    memory_limit, "--memory-limit GIB");
  }

  std::string run_help()
  {
    return "usage: cosim run CASE.prm [-o OUTDIR] [--set \"Section/Key=value\" ...] [--force] [--quiet]\n"
           "       cosim run --restart OUTDIR [-o NEWDIR] [--quiet]\n"
           "       cosim run --print-parameters > CASE.prm\n"
           "\n"
           "Runs one coupled UCS / BTS / CTCS case and writes into OUTDIR (default results/<case stem>):\n"
           "  summary.json         peak stress and force, modulus, Poisson's ratio, energy checks\n"
           "  history.csv          one row per output step (time_s, displacement_mm, force_kN, ...)\n"
           "  results.h5, .xdmf    history, particle and platen-mesh snapshots (open the .xdmf in ParaView)\n"
           "  curve.png            stress-strain (UCS, CTCS) or stress-displacement (BTS)\n"
           "  used_parameters.prm  every parameter as used, the rock group's values included\n"
           "\n"
           "options:\n"
           "  -o, --output OUTDIR  result folder; never replaced without --force\n"
           "  --set \"S/K=value\"    override one parameter (repeatable), e.g. --set \"SPH/Particle spacing=0.002\"\n"
           "  --force              replace an existing OUTDIR written by cosim (only once the run has\n"
           "                       succeeded; never the working folder, its parents or a folder cosim\n"
           "                       did not write)\n"
           "  --memory-limit GIB   memory the run may use (default 90 % of the available memory); a case\n"
           "                       whose estimate exceeds it is refused before it starts\n"
           "  --restart OUTDIR     continue an interrupted run from OUTDIR/checkpoint.h5 with\n"
           "                       OUTDIR/used_parameters.prm (into OUTDIR unless -o)\n"
           "  -q, --quiet          no progress display\n"
           "  --print-parameters   print a complete case file of the defaults (every key, its default\n"
           "                       and documentation) to stdout and exit\n"
           "\n"
           "The results are written into a hidden sibling folder and renamed to OUTDIR at the end, so a\n"
           "failed run never leaves a half-written or half-replaced OUTDIR. An unstable run keeps what it\n"
           "has in OUTDIR.failed.\n"
           "\n"
           "SIGINT / SIGTERM / SIGHUP: the run stops after the current step, writes checkpoint.h5 and what it\n"
           "has into OUTDIR (OUTDIR.interrupted when OUTDIR holds another result), and exits with 4 (a\n"
           "second signal kills at once). Periodic checkpoints:\n"
           "Output/Checkpoint interval (steps), Output/Checkpoint minutes.\n"
           "\n"
           "Exit status: 0 done, 2 bad input (one line on stderr, nothing written), 3 unstable run\n"
           "(OUTDIR.failed with last_good_state.h5), 4 interrupted (checkpoint written), 1 other failure.\n"
           "\n"
           "Case-file keys (deal.II ParameterHandler syntax: subsection S / set K = value / end; a\n"
           "CASE.json holds {\"Section\": {\"Key\": \"value\"}} instead), "
           "SI units, [default]:\n" +
           case_file_keys_help();
  }

  int run_main(const std::vector<std::string> &args)
  {
    RunOptions options = parse_options(args);
    if (options.print_parameters)
    {
      std::fputs(default_case_file().c_str(), stdout);
      return 0;
    }
    const CaseFile case_file = read_case_file(options.case_file, options.overrides);
    if (!options.restart.empty() && options.output.empty())
      options.output = options.restart; // a restart continues into its own folder
    const std::string output =
      options.output.empty() ? (fs::path("results") / fs::path(options.case_file).stem()).string() : options.output;
    const fs::path target = check_result_folder(output, options.force, {fs::path(options.case_file)}, options.restart);
    check_case_resources(case_file, options.memory_limit);
    for (const auto &w : case_file.warnings)
      std::fprintf(stderr, "cosim: warning: %s\n", w.c_str());
    return run_into_folder(case_file, target, options.force, options.quiet, nullptr, options.restart);
  }

  std::string shell_quote(const std::string &text)
  {
    bool plain = !text.empty();
    for (const char ch : text)
      plain = plain && (std::isalnum(static_cast<unsigned char>(ch)) || std::strchr("/._-+=:,@", ch));
    if (plain)
      return text;
    std::string out = "'";
    for (const char ch : text)
      out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
  }

  std::string shell_word(const std::string &text) { return clip(shell_quote(text)); }

  namespace
  {
    /// This process's MPI rank (0 where MPI is not initialised); every rank waits here until
    /// all have checked their input, so that rank 0 writes nothing before.
    int mpi_rank()
    {
      int initialised = 0, rank = 0, size = 1;
      MPI_Initialized(&initialised);
      if (!initialised)
        return 0;
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      if (size > 1)
        MPI_Barrier(MPI_COMM_WORLD);
      return rank;
    }

    /// What the ranks other than 0 observe: the stop signals (RunLoop agrees on a stop over all
    /// ranks) and the snapshots, whose particle rows every rank writes into rank 0's results.h5
    /// (write_particle_rows), and the checkpoints, which all ranks write together (write_checkpoint).
    class WorkerObserver : public RunObserver
    {
    public:
      bool stop_requested() override { return StopSignals::received() != 0; }
      void snapshot(double, const ParticleSnapshot &particles, const std::vector<MeshSnapshot> &) override
      {
        if (!particles.global_index.empty())
          write_particle_rows("", "", particles);
      }
      void checkpoint(std::size_t, const StateArrays &state, const coupling::StateRows *rows) override
      {
        if (rows) // rank 0's path and case
          write_checkpoint("", state, "", rows);
      }
    };

    /// A rank other than 0: its part of the run, with rank 0's exit status.
    int run_worker(const CaseFile &case_file, const StateArrays *resume)
    {
      WorkerObserver observer;
      try
      {
        run_case(case_file.parameters, observer, resume);
        return 0;
      }
      catch (const InstabilityError &)
      {
        return 3;
      }
      catch (const RunInterrupted &)
      {
        return 4;
      }
    }
  } // namespace

  int run_into_folder(const CaseFile &case_file, const std::filesystem::path &target, const bool force,
                      const bool quiet, Summary *result, const std::string &restart,
                      std::filesystem::path *interrupted_into)
  {
    StateArrays resume;
    if (!restart.empty())
    {
      // the checkpoint must belong to this folder's case, as used_parameters.prm holds it now
      const fs::path prm = fs::path(restart) / "used_parameters.prm";
      std::ifstream in(prm, std::ios::binary);
      std::ostringstream text;
      text << in.rdbuf();
      const std::string used = text.str();
      resume = read_checkpoint((fs::path(restart) / "checkpoint.h5").string(), &used);
    }
    std::error_code ec;
    const bool own_restart = !restart.empty() && fs::exists(target, ec) && fs::equivalent(target, restart, ec);

    // Signals first: from the moment the folder is claimed, a SIGINT / SIGTERM / SIGHUP ends the
    // run through the checkpoint path, never with a half-written staging folder.
    const StopSignals stop_signals;
    // MPI (mpirun -np N): every rank has checked the input alike; rank 0 writes, the others
    // run their part of the body and write nothing
    if (mpi_rank() != 0)
      return run_worker(case_file, restart.empty() ? nullptr : &resume);
    // Everything checked: from here on we write, but only into the staging folder.
    ResultFolder folder(target, "run");
    const fs::path &staging = folder.staging();
    try
    {
      write_text_file((staging / "used_parameters.prm").string(), case_file.used_parameters);
      ResultsFile results((staging / "results.h5").string());
      ProgressDisplay progress(case_file.parameters.output.progress && !quiet);
      if (!restart.empty())
      {
        // the interrupted run's snapshots up to its checkpoint come first
        const auto scalars = resume.find("driver.scalars");
        if (scalars != resume.end() && !scalars->second.empty())
          results.copy_snapshots((fs::path(restart) / "results.h5").string(), scalars->second[0]);
      }
      RecordingObserver observer(results, progress, staging, case_file.used_parameters);
      const auto start = std::chrono::steady_clock::now();
      auto write_all = [&](const Summary *summary, const RunEnd &end) {
        write_text_file((staging / "summary.json").string(), summary_json(summary, end));
        write_history_csv((staging / "history.csv").string(), observer.rows);
        results.write_history(observer.rows);
        results.close((staging / "results.xdmf").string());
        if (!observer.rows.empty())
        {
          const std::string why = plot_curve((staging / "history.csv").string(), case_file.parameters.test,
                                             (staging / "curve.png").string(), curve_labels(case_file));
          if (!why.empty())
            std::fprintf(stderr, "cosim: warning: %s\n", why.c_str());
        }
        const std::string &test = case_file.parameters.test;
        if (summary && (test == "UCS" || test == "BTS" || test == "CTCS"))
        {
          const std::string png = (staging / "failure_pattern.png").string();
          const std::string why =
            run_plot_script("plot_failure.py", {(staging / "results.h5").string(), test, png}, png);
          if (!why.empty())
            std::fprintf(stderr, "cosim: warning: %s\n", why.c_str());
        }
      };
      try
      {
        Summary summary =
          run_case(case_file.parameters, observer, restart.empty() ? nullptr : &resume);
        progress.finish();
        if (summary.wall_seconds <= 0)
          summary.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        write_all(&summary, RunEnd{});
        const fs::path published = folder.publish(ResultStatus::complete, force || own_restart);
        if (published != target)
          std::fprintf(stderr, "cosim: warning: %s appeared during the run and is not cosim's to replace; "
                       "the results are in %s\n", clip(target.string()).c_str(), clip(published.string()).c_str());
        if (result)
          *result = summary;
        if (!quiet)
        {
          // the laboratory tests report a strength; a cutter or indenter its forces
          const auto mean_normal = find_extra(summary, "mean_normal_force_kN");
          const auto peak_normal = find_extra(summary, "peak_normal_force_kN");
          if (mean_normal && peak_normal)
            std::fprintf(stderr, "cosim: %s: normal force mean %.1f kN, peak %.1f kN, %zu steps, %.1f s -> %s\n",
                         summary.test.c_str(), *mean_normal, *peak_normal, summary.n_steps, summary.wall_seconds,
                         clip(published.string()).c_str());
          else
            std::fprintf(stderr, "cosim: %s: peak %.2f MPa, %zu steps, %.1f s -> %s\n", summary.test.c_str(),
                         summary.peak_stress * 1e-6, summary.n_steps, summary.wall_seconds,
                         clip(published.string()).c_str());
        }
        return 0;
      }
      catch (const InstabilityError &e)
      {
        progress.finish();
        RunEnd end;
        end.status         = RunStatus::unstable;
        end.message        = e.what();
        end.test           = case_file.parameters.test;
        end.wall_seconds   = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        end.last_good_step = observer.good_step;
        end.last_good_time = observer.good_time;
        write_all(nullptr, end);
        write_text_file((staging / "failure.txt").string(), std::string(e.what()) + "\n");
        fs::path failed = target;
        failed += ".failed";
        failed = folder.publish(ResultStatus::failed, force, failed);
        std::fprintf(stderr, "cosim: unstable run: %s (what it had is in %s)\n", clip(e.what()).c_str(),
                     clip(failed.string()).c_str());
        return 3;
      }
      catch (const RunInterrupted &e)
      {
        progress.finish();
        // an interrupted run never replaces a result other than the one it continues: with the
        // target taken, it goes to OUTDIR.interrupted
        fs::path destination = target;
        if (fs::exists(fs::symlink_status(target, ec)) && !own_restart)
          destination += ".interrupted";
        const bool replace = own_restart || result_status(destination) == ResultStatus::interrupted;
        RunEnd end;
        end.status          = RunStatus::interrupted;
        end.message         = e.what();
        end.test            = case_file.parameters.test;
        end.wall_seconds    = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        end.n_steps         = observer.checkpoint_step;
        end.checkpoint      = "checkpoint.h5";
        end.restart_command = "cosim run --restart " + shell_word(destination.string());
        write_all(nullptr, end);
        const fs::path published = folder.publish(ResultStatus::interrupted, replace, destination);
        if (!interrupted_into) // a study says it in its own words
          std::fprintf(stderr, "cosim: %s; checkpoint in %s; continue with: cosim run --restart %s\n",
                       clip(e.what()).c_str(), clip((published / "checkpoint.h5").string()).c_str(),
                       shell_word(published.string()).c_str());
        if (interrupted_into)
          *interrupted_into = published;
        return 4;
      }
    }
    catch (const std::bad_alloc &)
    {
      throw;
    }
    catch (const InputError &)
    {
      throw;
    }
    catch (const std::runtime_error &e)
    {
      // I/O failures while writing (disk full, quota, a folder removed under us): one line
      // naming the folder; the staging folder is removed by ResultFolder
      throw std::runtime_error("writing the results of " + clip(target.string()) + " failed: " + clip(e.what()) +
                               " (disk full or not writable?)");
    }
  }
} // namespace app
