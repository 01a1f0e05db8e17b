// Ownership of result folders: up-front checks, the lock, the staging sibling and the atomic
// publication (app/result_folder.h).
#include <app/paths.h>
#include <app/result_folder.h>
#include <coupling/errors.h>
#include <diagnose/text_input.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <stdexcept>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace app
{
  namespace fs = std::filesystem;
  using coupling::InputError;
  using diagnose::clip;

  namespace
  {
    const char *status_name(const ResultStatus s)
    {
      switch (s)
      {
        case ResultStatus::complete:
          return "complete";
        case ResultStatus::interrupted:
          return "interrupted";
        case ResultStatus::failed:
          return "failed";
        default:
          return "none";
      }
    }

    /// The lock file of `target`: ".NAME.lock" in its parent.
    fs::path lock_path_of(const fs::path &target)
    {
      return target.parent_path() / ("." + target.filename().string() + ".lock");
    }

    /// True when `inner` is `outer` or lies below it (both canonical).
    bool is_within(const fs::path &inner, const fs::path &outer)
    {
      auto i = inner.begin();
      for (auto o = outer.begin(); o != outer.end(); ++o, ++i)
      {
        if (o->empty())
          continue; // a trailing separator
        if (i == inner.end() || *i != *o)
          return false;
      }
      return true;
    }

    fs::path canonical_or_normal(const fs::path &p)
    {
      std::error_code ec;
      const fs::path c = fs::weakly_canonical(fs::absolute(p, ec), ec);
      return ec ? fs::absolute(p).lexically_normal() : c;
    }

    bool is_empty_folder(const fs::path &p)
    {
      std::error_code ec;
      return fs::is_directory(fs::symlink_status(p, ec)) && fs::is_empty(p, ec) && !ec;
    }

    /// Whether another process holds the lock of `target` (without creating the lock file).
    bool locked_by_another(const fs::path &target)
    {
      const int fd = ::open(lock_path_of(target).c_str(), O_RDONLY | O_CLOEXEC);
      if (fd < 0)
        return false;
      const bool held = ::flock(fd, LOCK_SH | LOCK_NB) != 0 && errno == EWOULDBLOCK;
      ::close(fd);
      return held;
    }

    /// rename(2) that never replaces (`exchange` false) or swaps two existing paths atomically
    /// (`exchange` true). Returns 0 or an errno; EINVAL / ENOSYS when the file system lacks it.
    int rename_atomic(const fs::path &from, const fs::path &to, const bool exchange)
    {
      const unsigned int flags = exchange ? RENAME_EXCHANGE : RENAME_NOREPLACE;
      if (::renameat2(AT_FDCWD, from.c_str(), AT_FDCWD, to.c_str(), flags) == 0)
        return 0;
      return errno;
    }
  } // namespace

  fs::path sibling(const fs::path &target, const std::string &tag)
  {
    fs::path candidate;
    std::error_code ec;
    for (int i = 0;; ++i)
    {
      candidate = target.parent_path() / ("." + target.filename().string() + "." + tag + "-" +
                                          std::to_string(getpid()) + (i ? "-" + std::to_string(i) : ""));
      if (!fs::exists(fs::symlink_status(candidate, ec)))
        return candidate;
    }
  }

  ResultStatus result_status(const fs::path &folder)
  {
    std::ifstream in(folder / result_marker);
    std::string line;
    while (in && std::getline(in, line))
      if (line.rfind("status: ", 0) == 0)
      {
        const std::string s = line.substr(8);
        if (s == "complete")
          return ResultStatus::complete;
        if (s == "interrupted")
          return ResultStatus::interrupted;
        if (s == "failed")
          return ResultStatus::failed;
      }
    return ResultStatus::none;
  }

  fs::path check_result_folder(const std::string &output, const bool force, const std::vector<fs::path> &inputs,
                               const std::string &restart, const std::string &option)
  {
    if (output.empty())
      throw InputError(option + ": an empty folder name; give the result folder, e.g. " + option + " results/ucs");
    fs::path out = fs::absolute(fs::path(output)).lexically_normal();
    if (!out.has_filename())
      out = out.parent_path();
    const std::string shown = clip(out.string());
    std::error_code ec;
    const fs::file_status link = fs::symlink_status(out, ec);
    if (fs::is_symlink(link))
      throw InputError("output folder " + shown + " is a symbolic link" +
                       (fs::exists(out, ec) ? std::string() : std::string(" to nothing (dangling)")) +
                       "; give a real folder with " + option);
    if (fs::exists(link) && !fs::is_directory(link))
      throw InputError("output folder " + shown + " is an existing file; choose another with " + option);

    // never the working folder, its parents, the root or home, nor a folder that holds an input
    const fs::path real = canonical_or_normal(out);
    const fs::path cwd  = canonical_or_normal(fs::current_path(ec));
    if (real == real.root_path() || is_within(cwd, real))
      throw InputError("output folder " + shown +
                       " is the working folder or one of its parents; cosim never replaces it, give a new "
                       "folder with " + option + " (e.g. " + option + " results/run1)");
    if (const char *home = std::getenv("HOME"); home && *home && real == canonical_or_normal(home))
      throw InputError("output folder " + shown + " is the home folder; give a new folder with " + option);
    const bool own_restart = !restart.empty() && fs::exists(out, ec) && fs::equivalent(out, fs::path(restart), ec);
    if (!own_restart)
      for (const auto &input : inputs)
        if (!input.empty() && is_within(canonical_or_normal(input), real))
          throw InputError("output folder " + shown + " holds the input " + clip(input.string()) +
                           "; cosim never replaces its own input, give another folder with " + option);

    if (locked_by_another(out))
      throw InputError("output folder " + shown + " is being written by another cosim (lock " +
                       clip(lock_path_of(out).string()) + "); wait for it or choose another with " + option);
    if (fs::exists(link) && !own_restart)
    {
      if (!force)
        throw InputError("output folder " + shown + " already exists; use --force to replace it, or " + option +
                         " to choose another");
      if (result_status(out) == ResultStatus::none && !is_empty_folder(out))
        throw InputError("output folder " + shown + " was not written by cosim (no " + result_marker +
                         " in it); --force replaces only cosim's results: remove it yourself or choose another with " +
                         option);
    }
    // the nearest existing ancestor must be a writable folder
    fs::path ancestor = out.parent_path();
    while (!ancestor.empty() && !fs::exists(ancestor, ec) && ancestor != ancestor.root_path())
      ancestor = ancestor.parent_path();
    if (!fs::is_directory(ancestor, ec))
      throw InputError("output folder " + shown + ": " + clip(ancestor.string()) +
                       " is not a folder; choose a writable place with " + option);
    if (::access(ancestor.c_str(), W_OK | X_OK) != 0)
      throw InputError("output folder " + shown + ": " + clip(ancestor.string()) +
                       " is not writable; choose a writable place with " + option);
    return out;
  }

  ResultFolder::ResultFolder(const fs::path &target, const std::string &command)
    : target_(target)
    , command_(command)
  {
    std::error_code ec;
    for (fs::path p = target.parent_path(); !p.empty() && !fs::exists(p, ec) && p != p.root_path();
         p = p.parent_path())
      first_created_ = p;
    fs::create_directories(target.parent_path(), ec);
    auto fail = [&](const std::string &why) {
      if (!first_created_.empty())
        fs::remove_all(first_created_, ec);
      throw InputError("output folder " + clip(target.string()) + ": " + why);
    };
    if (ec)
      fail("cannot create " + clip(target.parent_path().string()) + " (" + ec.message() + ")");

    // the lock: flock on ".NAME.lock"; a lock file unlinked by its previous holder between our
    // open and our flock is not the lock any more, so take it again
    lock_path_ = lock_path_of(target);
    for (int attempt = 0; attempt < 10 && lock_fd_ < 0; ++attempt)
    {
      const int fd = ::open(lock_path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
      if (fd < 0)
        fail("cannot create the lock " + clip(lock_path_.string()) + " (" + std::strerror(errno) + ")");
      if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
      {
        ::close(fd);
        lock_path_.clear(); // not ours: never unlink it
        fail("is being written by another cosim; wait for it or choose another with -o");
      }
      struct stat by_fd = {}, by_path = {};
      if (::fstat(fd, &by_fd) == 0 && ::stat(lock_path_.c_str(), &by_path) == 0 && by_fd.st_ino == by_path.st_ino &&
          by_fd.st_dev == by_path.st_dev)
        lock_fd_ = fd;
      else
        ::close(fd);
    }
    if (lock_fd_ < 0)
      fail("cannot take the lock " + clip(lock_path_.string()));
    const std::string pid = std::to_string(getpid()) + "\n";
    if (::ftruncate(lock_fd_, 0) == 0 && ::write(lock_fd_, pid.data(), pid.size()) < 0)
    {
      // the pid is for people only; the flock is the lock
    }

    staging_ = sibling(target, "tmp");
    if (!fs::create_directory(staging_, ec))
    {
      ::unlink(lock_path_.c_str());
      ::close(lock_fd_);
      lock_fd_ = -1;
      fail("cannot create " + clip(staging_.string()) + " (" + ec.message() + "); choose a writable place with -o");
    }
  }

  ResultFolder::~ResultFolder()
  {
    std::error_code ec;
    if (!published_ && !keep_)
    {
      fs::remove_all(staging_, ec);
    }
    if (lock_fd_ >= 0)
    {
      ::unlink(lock_path_.c_str()); // while holding it: a waiting process re-checks the inode
      ::close(lock_fd_);
    }
    if (!published_ && !keep_ && !first_created_.empty())
      fs::remove_all(first_created_, ec);
  }

  fs::path ResultFolder::publish(const ResultStatus status, const bool replace, const fs::path &destination)
  {
    const fs::path dest = destination.empty() ? target_ : destination;
    {
      std::ofstream marker(staging_ / result_marker);
      marker << "cosim " << version() << " (commit " << commit() << ")\n"
             << "command: " << command_ << "\n"
             << "status: " << status_name(status) << "\n";
      if (!marker)
      {
        keep_ = true;
        throw std::runtime_error("cannot write " + clip((staging_ / result_marker).string()) +
                                 "; the results are in " + clip(staging_.string()));
      }
    }
    std::error_code ec;
    auto fresh_sibling = [&](const fs::path &base) {
      fs::path p = base;
      p += ".new-" + std::to_string(getpid());
      for (int i = 1; fs::exists(fs::symlink_status(p, ec)); ++i)
      {
        p = base;
        p += ".new-" + std::to_string(getpid()) + "-" + std::to_string(i);
      }
      return p;
    };
    fs::path where = dest;
    int error      = 0;
    const fs::file_status existing = fs::symlink_status(dest, ec);
    if (fs::exists(existing))
    {
      const bool ours = fs::is_directory(existing) &&
                        (result_status(dest) != ResultStatus::none || is_empty_folder(dest));
      if (replace && ours)
      {
        error = rename_atomic(staging_, dest, true);
        if (error == EINVAL || error == ENOSYS)
        {
          // no RENAME_EXCHANGE here: move the old result aside, then rename (a short window)
          const fs::path old = sibling(dest, "old");
          fs::rename(dest, old, ec);
          if (!ec)
            fs::rename(staging_, dest, ec);
          error = ec ? ec.value() : 0;
          if (!error)
            fs::remove_all(old, ec);
        }
        else if (!error)
          fs::remove_all(staging_, ec); // staging_ now holds the old result
      }
      else
        where = fresh_sibling(dest);
    }
    if (where != dest || !fs::exists(existing))
    {
      error = rename_atomic(staging_, where, false);
      if (error == EEXIST)
      {
        // appeared in the meantime: never replace it
        where = fresh_sibling(dest);
        error = rename_atomic(staging_, where, false);
      }
      if (error == EINVAL || error == ENOSYS)
      {
        fs::rename(staging_, where, ec);
        error = ec ? ec.value() : 0;
      }
    }
    if (error)
    {
      keep_ = true;
      throw std::runtime_error("cannot publish the results to " + clip(where.string()) + " (" + std::strerror(error) +
                               "); they are in " + clip(staging_.string()));
    }
    published_ = true;
    return where;
  }
} // namespace app
