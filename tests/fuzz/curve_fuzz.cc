// libFuzzer target for the curve files of `cosim diagnose` (curves/*.csv: `# key: value` header
// lines, then time_s,displacement_mm,force_kN): any bytes as the only curve of a data folder give
// a curve or a one-line InputError (fuzz_contract.h); nothing else.
// Built and run by tools/sanitize (clang++-14 -fsanitize=fuzzer,address,undefined).
#include "fuzz_contract.h"

#include <diagnose/diagnose.h>

#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
  namespace fs = std::filesystem;
  static const fs::path folder = fs::temp_directory_path() / ("cosim-curve-fuzz-" + std::to_string(getpid()));
  fs::create_directories(folder / "curves");
  std::ofstream(folder / "curves" / "c.csv", std::ios::binary | std::ios::trunc)
    << std::string(reinterpret_cast<const char *>(data), size);
  try
  {
    const diagnose::Data d = diagnose::read_data(folder.string());
    // what reaches the fit: finite, increasing time, a positive peak force, enough rows
    for (const auto &c : d.curves)
    {
      double peak = 0;
      for (std::size_t i = 0; i < c.time.size(); ++i)
      {
        if (!std::isfinite(c.time[i]) || !std::isfinite(c.force[i]) || (i > 0 && !(c.time[i] > c.time[i - 1])))
          std::abort();
        peak = std::max(peak, c.force[i]);
      }
      // a failed specimen may give its peak row only; a curve without failure needs its points
      if (!(peak > 0) || c.time.empty() || (!c.failed && c.time.size() < 5) ||
          !(c.diameter > 0 && c.length > 0))
        std::abort();
    }
  }
  catch (const coupling::InputError &e)
  {
    cosim_fuzz::check_message(e);
  }
  return 0;
}
