#pragma once
// Runs the built cosim in a fresh temporary folder and reports status, stderr and what it wrote.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

namespace cosim_test
{
  namespace fs = std::filesystem;

  inline std::string cosim_binary() { return std::string(COSIM_BINARY_DIR) + "/coupling/cosim"; }
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
} // namespace cosim_test
