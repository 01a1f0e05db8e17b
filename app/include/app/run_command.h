#pragma once
/// @file
/// `cosim run`: read and check a case, run it, write the result folder atomically. The pieces
/// (output-folder check, staging sibling, publish, run into a folder) are shared with `cosim study`.

#include <app/case_file.h>
#include <coupling/run_output.h>

#include <filesystem>
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

  /// The absolute result folder for `output` (default results/<case_stem> when empty), checked
  /// before anything is written: InputError when it is a file, exists without `force`, or its
  /// nearest existing ancestor is not a writable folder. `restart`: the folder a restart
  /// continues in, which may exist.
  std::filesystem::path check_output_folder(const std::string &output, const std::string &case_stem, bool force,
                                            const std::string &restart = "");

  /// A hidden sibling of `target` (".name.TAG-PID[-i]") that does not exist yet.
  std::filesystem::path sibling(const std::filesystem::path &target, const std::string &tag);

  /// Renames `staging` to `target`; an existing `target` is moved aside first and removed only
  /// after the rename, so `target` is never half replaced.
  void publish(const std::filesystem::path &staging, const std::filesystem::path &target);

  /// Runs a read case and writes its result folder `target` (checked by check_output_folder)
  /// through a staging sibling. Returns 0 (and the summary in `*result` when not null) or 3 for
  /// an unstable run, whose partial results go to `target`.failed. `quiet`: no progress display
  /// and no closing line. `restart`: continue from that folder's checkpoint.h5.
  int run_into_folder(const CaseFile &case_file, const std::filesystem::path &target, bool force, bool quiet,
                      coupling::Summary *result, const std::string &restart = "");
} // namespace app
