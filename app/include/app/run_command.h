#pragma once
/// @file
/// `cosim run`: read and check a case, run it, write the result folder atomically. The pieces
/// (output-folder check, staging sibling, publish, run into a folder) are shared with `cosim study`.

#include <app/case_file.h>
#include <app/cli.h>
#include <coupling/run_output.h>

#include <csignal>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace app
{
  /// `cosim run CASE.prm [-o OUTDIR] [--set "Section/Key=value" ...] [--force] [--quiet]`
  /// (arguments after the subcommand). Returns the exit status: 0 done, 2 bad input,
  /// 3 unstable run, 1 other failure.
  int run_main(const std::vector<std::string> &args);
  /// Help text of `cosim run`.
  std::string run_help();

  /// Handles SIGINT, SIGTERM and SIGHUP while alive: the first one sets a flag the time loop
  /// polls (the run stops with a checkpoint), a second of the same kind ends the process at once.
  /// Nestable: an inner instance (a run inside a study) leaves the outer one's handling in place.
  class StopSignals
  {
  public:
    StopSignals();
    ~StopSignals();
    StopSignals(const StopSignals &)            = delete;
    StopSignals &operator=(const StopSignals &) = delete;
    /// The signal received since the outermost instance was made, or 0.
    static int received();

  private:
    struct sigaction old_int_ = {}, old_term_ = {}, old_hup_ = {};
  };

  /// The value of `option` (just read by `cursor`) as a memory limit in GiB, in bytes.
  std::optional<double> memory_limit_option(ArgumentCursor &cursor, const std::string &option);

  /// InputError when the case's resource estimate exceeds `memory_limit` (bytes; default: 90 %
  /// of the available memory), naming the estimate and the finest spacing that fits.
  void check_case_resources(const CaseFile &case_file, const std::optional<double> &memory_limit);

  /// `text` as one POSIX shell word, single-quoted when it holds anything but [A-Za-z0-9/._-+=:,@].
  std::string shell_quote(const std::string &text);

  /// shell_quote(text), clipped for a message.
  std::string shell_word(const std::string &text);

  /// Runs a read case and writes its result folder `target` (checked by check_output_folder)
  /// through a staging sibling. Returns 0 (and the summary in `*result` when not null) or 3 for
  /// an unstable run, whose partial results go to `target`.failed. `quiet`: no progress display
  /// and no closing line. `restart`: continue from that folder's checkpoint.h5. Returns 4 when a
  /// signal stopped the run, with the folder its checkpoint went to in `*interrupted_into`.
  int run_into_folder(const CaseFile &case_file, const std::filesystem::path &target, bool force, bool quiet,
                      coupling::Summary *result, const std::string &restart = "",
                      std::filesystem::path *interrupted_into = nullptr);
} // namespace app
