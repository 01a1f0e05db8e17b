#pragma once
/// @file
/// Ownership of result folders, shared by `cosim run`, `study` and `diagnose`:
/// - cosim replaces or removes only folders it wrote: each published folder holds the marker file
///   `.cosim-result` (the command, the outcome and the version); a folder without it is never
///   replaced, --force or not;
/// - never the working folder, one of its parents, the file-system root or home folder, nor a
///   folder that holds the command's own input (case file, data folder);
/// - a symbolic link, a file, an unwritable place or an empty name is refused up front (exit 2);
/// - while a command writes, it holds a lock (`.NAME.lock` beside OUTDIR, flock); a second command
///   into the same OUTDIR is refused;
/// - results are written into a hidden staging sibling and published by one atomic rename (an
///   existing result is exchanged with the staging folder by renameat2(RENAME_EXCHANGE) and only
///   then removed), so OUTDIR is at every moment either the old or the new result.

#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace app
{
  /// Name of the marker file cosim writes into every result folder it publishes.
  inline constexpr const char *result_marker = ".cosim-result";

  /// What a result folder holds, as its marker says.
  enum class ResultStatus
  {
    none,        ///< no marker: not written by cosim (or by a version before markers)
    complete,    ///< a finished run, study or diagnosis
    interrupted, ///< a run stopped by a signal, with checkpoint.h5
    failed,      ///< an unstable run's partial results (OUTDIR.failed)
  };

  /// A hidden sibling of `target` (".name.TAG-PID[-i]") that does not exist yet.
  std::filesystem::path sibling(const std::filesystem::path &target, const std::string &tag);

  /// The status recorded in `folder`'s marker; none when there is no readable marker.
  ResultStatus result_status(const std::filesystem::path &folder);

  /// Up-front checks of a result folder before anything is read or written. Returns the absolute,
  /// normalised folder. InputError (one line, naming `option` and the folder) when `output` is
  /// empty; is a symbolic link (dangling or not) or a file; is the working folder, one of its
  /// parents, the root or $HOME; contains one of `inputs`; exists without `force` (unless it is
  /// `restart`, the folder a restart continues in); exists with `force` but was not written by
  /// cosim (no marker); is being written by another cosim (locked); or lies where no folder can
  /// be made (nearest existing ancestor not a writable folder).
  std::filesystem::path check_result_folder(const std::string &output, bool force,
                                            const std::vector<std::filesystem::path> &inputs = {},
                                            const std::string &restart = "",
                                            const std::string &option  = "-o");

  /// One command's claim on a result folder: the lock, the staging sibling and the publication.
  /// Lifecycle: construct (creates missing parents, takes the lock, creates the staging folder),
  /// write into staging(), then publish() once; the destructor removes an unpublished staging
  /// folder, the parents it created and the lock.
  class ResultFolder
  {
  public:
    /// `target`: as returned by check_result_folder. `command`: "run", "study", "diagnose" (for
    /// the marker). InputError when the lock is held by another process or staging cannot be made.
    ResultFolder(const std::filesystem::path &target, const std::string &command);
    ~ResultFolder();
    ResultFolder(const ResultFolder &)            = delete;
    ResultFolder &operator=(const ResultFolder &) = delete;

    /// The hidden folder to write into (".NAME.tmp-PID").
    const std::filesystem::path &staging() const { return staging_; }
    /// The folder results go to.
    const std::filesystem::path &target() const { return target_; }

    /// Writes the marker with `status` into staging and renames staging to `destination`
    /// (default target()) atomically. An existing destination is replaced only when `replace` is
    /// true and it carries a cosim marker; otherwise the results go to a fresh sibling
    /// "DESTINATION.new-PID" and that path is returned. std::runtime_error (with the staging
    /// folder kept and named) when the rename fails.
    std::filesystem::path publish(ResultStatus status, bool replace,
                                  const std::filesystem::path &destination = {});

    /// Keeps the staging folder (no cleanup); for results that must not be lost after a failed
    /// publication.
    void keep_staging() { keep_ = true; }

  private:
    std::filesystem::path target_, staging_, first_created_, lock_path_;
    std::string command_;
    int lock_fd_   = -1;
    bool published_ = false, keep_ = false;
  };
} // namespace app
