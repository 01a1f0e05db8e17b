// cosim: the command-line front end. Each subcommand is one row of `commands` below: a name, a
// one-line summary, its help text and its entry point (arguments after the subcommand, returns
// the exit status). To add one, write `int my_main(const std::vector<std::string>&)` and
// `std::string my_help()` in app/src and add a row.
//
// Exit status (docs/design.md): 0 done, 1 internal failure, 2 bad input (one line on stderr
// naming the culprit and what is accepted), 3 unstable run.
//
// MPI: under `mpirun -np N` (a launcher's environment) cosim initialises MPI and every rank runs
// the same command; only rank 0 prints (the others' stdout and stderr go to /dev/null) and writes
// files, and every rank ends with the same exit status. Started without a launcher it runs as one
// process without initialising MPI at all: Open MPI's singleton start-up (a daemon and shared
// memory files) fails under a file-size limit, and PETSc (cosim diagnose) initialises MPI itself.
#include <app/calibrate_command.h>
#include <app/cli.h>
#include <app/diagnose_command.h>
#include <app/paths.h>
#include <app/reference_command.h>
#include <app/run_command.h>
#include <app/study.h>
#include <coupling/errors.h>
#include <diagnose/text_input.h>

#include <mpi.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>
#include <vector>

namespace
{
  struct Command
  {
    const char *name;
    const char *summary;
    std::string (*help)();
    int (*main)(const std::vector<std::string> &args);
  };

  const Command commands[] = {
    {"run", "run one UCS / BTS / CTCS case from a .prm file", &app::run_help, &app::run_main},
    {"calibrate", "back-calculate Mohr-Coulomb c, phi from UCS and BTS (Eqs. 14-15)", &app::calibrate_help,
     &app::calibrate_main},
    {"study", "sweep parameters / rock groups over one case: study.csv and study.png", &app::study_help,
     &app::study_main},
    {"diagnose", "what the simulation gets wrong on measured data, the cause and the gain",
     &app::diagnose_help, &app::diagnose_main},
    {"reference", "implicit axisymmetric FE reference of a UCS case: curve, peak, end-face stress",
     &app::reference_help, &app::reference_main},
  };

  std::vector<std::string> command_names()
  {
    std::vector<std::string> names;
    for (const auto &c : commands)
      names.push_back(c.name);
    return names;
  }

  std::string general_help()
  {
    std::string text = "usage: cosim SUBCOMMAND [options]\n"
                       "\n"
                       "SPH-FEM co-simulation of laboratory rock tests (UCS, BTS, triaxial CTCS).\n"
                       "\n"
                       "subcommands:\n";
    for (const auto &c : commands)
    {
      std::string name = c.name;
      name.resize(12, ' ');
      text += "  " + name + c.summary + "\n";
    }
    text += "\n'cosim SUBCOMMAND --help' describes one. Example:\n"
            "  cosim run cases/ucs/ucs.prm --set \"Rock/Group=M4\" -o results/ucs-M4\n"
            "\n"
            "  cosim --version    the version and the commit it was built from\n"
            "\n"
            "Exit status: 0 done, 2 bad input, 3 unstable run, 4 interrupted by a signal, 1 other failure.\n";
    return text;
  }

  /// One line on stderr, the last guard of the one-line contract: newlines folded into spaces,
  /// control and non-UTF-8 bytes (NUL included) shown as \xNN, at most ~600 characters (three
  /// clipped echoes of input and the text around them).
  void error_line(const std::string &message)
  {
    std::string line = message;
    for (auto &ch : line)
      if (ch == '\n' || ch == '\r')
        ch = ' ';
    line = diagnose::clip(line, 600);
    std::fwrite("cosim: ", 1, 7, stderr);
    std::fwrite(line.data(), 1, line.size(), stderr);
    std::fputc('\n', stderr);
  }

  /// Ends the process with `status` after an error without running atexit handlers: a library
  /// (HDF5) whose file was left open by a failed write would otherwise flush it again at exit,
  /// into a folder already removed, and crash. Everything of ours is cleaned up by then.
  /// Whether main initialised MPI (see MpiSession).
  bool mpi_started_here = false;

  [[noreturn]] void exit_after_error(const int status)
  {
    std::fflush(stdout);
    std::fflush(stderr);
    if (mpi_started_here) // (not MPI that PETSc started for cosim diagnose)
    {
      int size = 1;
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      // bad input, an unstable or interrupted run: every rank gets there alike; anything else
      // may have left the other ranks waiting in a collective
      if (size > 1 && status == 1)
        MPI_Abort(MPI_COMM_WORLD, status);
      MPI_Finalize();
    }
    std::_Exit(status);
  }

  /// Whether an MPI launcher started this process (Open MPI's mpirun, or a PMI/PMIx one).
  bool launched_by_mpirun()
  {
    for (const char *name : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK", "PMI_SIZE"})
      if (std::getenv(name) != nullptr)
        return true;
    return false;
  }

  /// Under a launcher: MPI for the process's lifetime; on ranks other than 0, stdout and stderr
  /// go to /dev/null. Otherwise nothing (one process, MPI not initialised).
  struct MpiSession
  {
    MpiSession(int &argc, char **&argv)
    {
      if (!launched_by_mpirun())
        return;
      initialised      = true;
      mpi_started_here = true;
      int provided     = 0;
      MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
      MPI_Comm_rank(MPI_COMM_WORLD, &rank);
      MPI_Comm_size(MPI_COMM_WORLD, &size);
      if (rank != 0)
      {
        if (!std::freopen("/dev/null", "w", stdout) || !std::freopen("/dev/null", "w", stderr))
          std::_Exit(1);
      }
    }
    ~MpiSession()
    {
      if (initialised)
        MPI_Finalize();
    }
    bool initialised = false;
    int  rank = 0, size = 1;
  };

  int run_command_line(const std::vector<std::string> &args, int n_ranks);
} // namespace

int main(int argc, char **argv)
{
  const MpiSession mpi(argc, argv);
  return run_command_line(std::vector<std::string>(argv + 1, argv + argc), mpi.size);
}

namespace
{
  int run_command_line(const std::vector<std::string> &args, const int n_ranks)
  {
  if (args.empty())
  {
    std::fputs(general_help().c_str(), stderr);
    return 2;
  }
  if (args[0] == "--help" || args[0] == "-h" || args[0] == "help")
  {
    std::fputs(general_help().c_str(), stdout);
    return 0;
  }
  if (args[0] == "--version" || args[0] == "version")
  {
    std::printf("cosim %s (commit %s)\n", app::version().c_str(), app::commit().c_str());
    return 0;
  }
  const Command *command = nullptr;
  for (const auto &c : commands)
    if (args[0] == c.name)
      command = &c;
  if (command == nullptr)
  {
    std::string names;
    for (const auto &n : command_names())
      names += (names.empty() ? "" : ", ") + n;
    error_line("unknown subcommand '" + diagnose::clip(args[0]) + "'" + app::did_you_mean(args[0], command_names()) +
               "; accepted: " + names + " (cosim --help)");
    return 2;
  }
  const std::vector<std::string> rest(args.begin() + 1, args.end());
  if (n_ranks > 1 && std::string(command->name) != "run")
  {
    error_line(std::string("cosim ") + command->name + " runs on one MPI rank only (" +
               std::to_string(n_ranks) + " given); run it without mpirun or with -np 1");
    return 2;
  }
  for (const auto &a : rest)
    if (a == "--help" || a == "-h")
    {
      std::fputs(command->help().c_str(), stdout);
      return 0;
    }
  int status = 0;
  try
  {
    status = command->main(rest);
  }
  catch (const coupling::InputError &e)
  {
    error_line(e.what());
    exit_after_error(2);
  }
  catch (const coupling::InstabilityError &e)
  {
    error_line(std::string("unstable run: ") + e.what());
    exit_after_error(3);
  }
  catch (const std::bad_alloc &)
  {
    error_line("out of memory (try a coarser SPH/Particle spacing, or see --memory-limit)");
    exit_after_error(1);
  }
  catch (const std::exception &e)
  {
    error_line(std::string("error: ") + e.what());
    exit_after_error(1);
  }
  return status;
}
} // namespace
