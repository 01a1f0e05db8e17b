#include <app/paths.h>

#include <cstdlib>
#include <system_error>

namespace app
{
  namespace fs = std::filesystem;

  fs::path executable_path()
  {
    std::error_code error;
    const fs::path self = fs::read_symlink("/proc/self/exe", error);
    return error ? fs::path("cosim") : self;
  }

  fs::path share_directory()
  {
    return executable_path().parent_path().parent_path() / "share" / "cosim";
  }

  namespace
  {
    fs::path from_environment(const char *name, const fs::path &fallback)
    {
      const char *value = std::getenv(name);
      return value != nullptr && *value != '\0' ? fs::path(value) : fallback;
    }
  } // namespace

  fs::path data_directory()
  {
    return from_environment("COSIM_DATA_DIR", share_directory() / "data");
  }

  fs::path script_directory()
  {
    return from_environment("COSIM_SCRIPT_DIR", share_directory() / "scripts");
  }

  std::string version() { return COSIM_VERSION; }

  std::string commit() { return COSIM_COMMIT; }
} // namespace app
