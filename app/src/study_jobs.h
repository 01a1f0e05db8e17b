#pragma once
/// @file
/// The runs of a study as `cosim run` commands: printed for a batch system (`--print-commands`)
/// or run side by side as child processes (`--jobs N`).
#include <cstddef>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace app
{
  /// One `cosim run` of a study.
  struct RunCommand
  {
    std::vector<std::string> argv;  ///< program and arguments
    std::filesystem::path folder;   ///< the run's result folder (its -o)
  };

  /// `argv` as one POSIX shell line, each word quoted where needed (never shortened).
  std::string command_line(const std::vector<std::string> &argv);

  /// Runs `commands` as child processes, at most `jobs` at a time, in their order. Each child
  /// gets OMP_NUM_THREADS=`threads` and its stderr in "<folder>.log"; it runs in its own process
  /// group and receives SIGTERM when this process dies. After SIGINT / SIGTERM / SIGHUP
  /// (StopSignals::received()) no further child starts and the running ones get one SIGTERM, so
  /// each stops with its checkpoint. `on_end(i, status)` is called as command i ends, with its
  /// exit status (-1: killed or not started); commands never started get no call.
  void run_side_by_side(const std::vector<RunCommand> &commands, int jobs, int threads,
                        const std::function<void(std::size_t, int)> &on_end);
} // namespace app
