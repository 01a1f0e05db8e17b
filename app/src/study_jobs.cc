#include "study_jobs.h"

#include <app/output_writer.h>
#include <app/run_command.h>

#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <map>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

extern char **environ;

namespace app
{
  std::string command_line(const std::vector<std::string> &argv)
  {
    std::string line;
    for (const auto &word : argv)
      line += (line.empty() ? "" : " ") + shell_quote(word);
    return line;
  }

  namespace
  {
    /// The environment of this process with OMP_NUM_THREADS set to `threads`.
    std::vector<std::string> child_environment(const int threads)
    {
      std::vector<std::string> env;
      for (char **e = environ; e && *e; ++e)
        if (std::strncmp(*e, "OMP_NUM_THREADS=", 16) != 0)
          env.emplace_back(*e);
      env.push_back("OMP_NUM_THREADS=" + std::to_string(threads));
      return env;
    }

    /// Starts one child; its pid, or -1.
    pid_t start(const RunCommand &command, const std::vector<std::string> &env)
    {
      // everything the child needs is built before fork: after it only async-signal-safe calls
      std::vector<char *> args, envp;
      for (const auto &a : command.argv)
        args.push_back(const_cast<char *>(a.c_str()));
      args.push_back(nullptr);
      for (const auto &e : env)
        envp.push_back(const_cast<char *>(e.c_str()));
      envp.push_back(nullptr);
      const std::string log = command.folder.string() + ".log";
      const pid_t parent    = getpid();
      const pid_t pid       = fork();
      if (pid != 0)
        return pid;
      setpgid(0, 0); // a terminal's SIGINT reaches the study, which forwards one SIGTERM
      prctl(PR_SET_PDEATHSIG, SIGTERM);
      if (getppid() != parent)
        _exit(127); // the study died before prctl took effect
      redirect_child_output(log.c_str());
      execve(args[0], args.data(), envp.data());
      _exit(127);
    }
  } // namespace

  void run_side_by_side(const std::vector<RunCommand> &commands, const int jobs, const int threads,
                        const std::function<void(std::size_t, int)> &on_end)
  {
    if (jobs < 1 || threads < 1)
      throw std::logic_error("run_side_by_side: jobs and threads must be positive");
    const std::vector<std::string> env = child_environment(threads);
    std::map<pid_t, std::size_t> running;
    std::size_t next     = 0;
    bool forwarded       = false;
    while (next < commands.size() || !running.empty())
    {
      const bool stopping = StopSignals::received() != 0;
      if (stopping && !forwarded)
      {
        for (const auto &[pid, i] : running)
          kill(pid, SIGTERM);
        forwarded = true;
      }
      while (!stopping && next < commands.size() && running.size() < static_cast<std::size_t>(jobs))
      {
        const pid_t pid = start(commands[next], env);
        if (pid < 0)
          on_end(next, -1);
        else
          running[pid] = next;
        ++next;
      }
      if (stopping && running.empty())
        break;
      int status      = 0;
      const pid_t pid = waitpid(-1, &status, WNOHANG);
      if (pid > 0)
      {
        const auto it = running.find(pid);
        if (it == running.end())
          continue; // not one of ours
        const std::size_t i = it->second;
        running.erase(it);
        on_end(i, WIFEXITED(status) ? WEXITSTATUS(status) : -1);
      }
      else if (pid < 0 && errno == ECHILD)
      {
        for (const auto &[lost, i] : running) // reaped elsewhere: the status is lost
          on_end(i, -1);
        running.clear();
      }
      else
        usleep(50000);
    }
  }
} // namespace app
