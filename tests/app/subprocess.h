#pragma once
// Runs the built cosim in a fresh temporary folder and reports status, stderr and what it wrote.
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>
#include <vector>

namespace cosim_test
{
  namespace fs = std::filesystem;

  /// The cosim under test: $COSIM_TEST_BINARY when set (to run a suite against another build),
  /// else the one of this build tree.
  inline std::string cosim_binary()
  {
    if (const char *other = std::getenv("COSIM_TEST_BINARY"); other && *other)
      return other;
    return std::string(COSIM_BINARY_DIR) + "/bin/cosim";
  }
  inline std::string source(const std::string &relative) { return std::string(COSIM_SOURCE_DIR) + "/" + relative; }

  inline std::string shell_quote(const std::string &s)
  {
    std::string out = "'";
    for (const char ch : s)
      out += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
    return out + "'";
  }

  inline std::string read_file(const fs::path &p)
  {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }

  /// Every path under `dir`, relative, hidden ones included.
  inline std::set<std::string> listing(const fs::path &dir)
  {
    std::set<std::string> out;
    for (const auto &e : fs::recursive_directory_iterator(dir))
      out.insert(fs::relative(e.path(), dir).string());
    return out;
  }

  /// A temporary working folder, removed at the end.
  class Sandbox
  {
  public:
    Sandbox()
    {
      std::string pattern = (fs::temp_directory_path() / "cosim-app-test-XXXXXX").string();
      dir_ = mkdtemp(pattern.data());
    }
    ~Sandbox()
    {
      std::error_code ec;
      fs::permissions(dir_, fs::perms::owner_all, fs::perm_options::add, ec);
      fs::remove_all(dir_, ec);
    }
    const fs::path &dir() const { return dir_; }
    fs::path write(const std::string &name, const std::string &text) const
    {
      const fs::path p = dir_ / name;
      fs::create_directories(p.parent_path());
      std::ofstream(p) << text;
      return p;
    }

  private:
    fs::path dir_;
  };

  struct Result
  {
    int status = -1;
    std::string out, err;
  };

  /// Runs cosim with `args` inside `sandbox`; stdout and stderr are captured outside it.
  inline Result run_cosim(const Sandbox &sandbox, const std::vector<std::string> &args)
  {
    const fs::path capture = fs::path(sandbox.dir().string() + ".capture");
    fs::create_directories(capture);
    std::string command = "cd " + shell_quote(sandbox.dir().string()) + " && " + shell_quote(cosim_binary());
    for (const auto &a : args)
      command += " " + shell_quote(a);
    command += " >" + shell_quote((capture / "out").string()) + " 2>" + shell_quote((capture / "err").string());
    const int raw = std::system(command.c_str());
    Result r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = read_file(capture / "out");
    r.err = read_file(capture / "err");
    fs::remove_all(capture);
    return r;
  }

  /// What sigterm_at_first_checkpoint saw.
  struct Interrupted
  {
    bool checkpoint_seen = false; ///< a periodic checkpoint appeared before the signal
    int  status          = -1;    ///< exit status of cosim, -1 if it did not exit normally
  };

  /// Starts cosim with `args` in the sandbox (stderr to /dev/null), waits up to `wait_s` seconds
  /// for the first periodic checkpoint in its temporary result folder (".NAME.tmp..."), which shows
  /// that the time loop runs, then sends SIGTERM and waits for it to exit.
  inline Interrupted sigterm_at_first_checkpoint(const Sandbox &sandbox,
                                                  std::vector<std::string> args,
                                                  const double wait_s)
  {
    Interrupted r;
    const std::string binary = cosim_binary();
    const pid_t       pid    = fork();
    if (pid < 0)
      return r;
    if (pid == 0)
    {
      if (chdir(sandbox.dir().c_str()) != 0)
        _exit(127);
      const int null = open("/dev/null", O_WRONLY);
      dup2(null, 2);
      std::vector<char *> argv;
      argv.push_back(const_cast<char *>(binary.c_str()));
      for (auto &a : args)
        argv.push_back(a.data());
      argv.push_back(nullptr);
      execv(binary.c_str(), argv.data());
      _exit(127);
    }
    const auto start = std::chrono::steady_clock::now();
    while (!r.checkpoint_seen &&
           std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() < wait_s)
    {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      for (const auto &e : fs::directory_iterator(sandbox.dir()))
      {
        const std::string name = e.path().filename().string();
        r.checkpoint_seen      = r.checkpoint_seen ||
                            (name.rfind(".", 0) == 0 && name.find(".tmp") != std::string::npos &&
                             fs::exists(e.path() / "checkpoint.h5"));
      }
    }
    kill(pid, SIGTERM);
    int status = 0;
    waitpid(pid, &status, 0);
    r.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    return r;
  }
} // namespace cosim_test
