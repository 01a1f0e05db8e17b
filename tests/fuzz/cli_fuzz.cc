// libFuzzer target for the command line: the input, split at newlines, is a subcommand's argument
// list walked as `cosim run` walks it (ArgumentCursor: options with values, --opt=value, numbers,
// memory limits), with every -o value put through the result-folder checks (check_result_folder,
// which writes nothing). Any arguments give options or a one-line, short, UTF-8 InputError
// (fuzz_contract.h); nothing is written; nothing else happens.
// Built and run by tools/sanitize (clang++-14 -fsanitize=fuzzer,address,undefined).
#include "fuzz_contract.h"

#include <app/cli.h>
#include <app/resource_estimate.h>
#include <app/result_folder.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <unistd.h>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
  namespace fs = std::filesystem;
  // an empty folder the checks must leave empty: every -o is also tried inside it
  static const fs::path sandbox = [] {
    const fs::path p = fs::temp_directory_path() / ("cosim-cli-fuzz-" + std::to_string(getpid()));
    fs::create_directories(p / "work");
    return p;
  }();
  std::vector<std::string> args;
  std::string text(reinterpret_cast<const char *>(data), size), item;
  for (const char ch : text)
    if (ch == '\n')
      args.push_back(item), item.clear();
    else
      item += ch;
  args.push_back(item);
  try
  {
    app::ArgumentCursor cursor("run", args);
    bool force = false;
    std::vector<std::string> outputs;
    while (!cursor.done())
    {
      const std::string a = cursor.next();
      if (a == "-o" || a == "--output")
        outputs.push_back(cursor.value(a));
      else if (a == "--set" || a == "--restart")
        (void)cursor.value(a);
      else if (a == "--memory-limit" || a == "--bic-threshold")
      {
        const double v = cursor.number(a);
        app::check_resources(app::estimate_for_volume(1e-4, 0.005), "fuzz", v * 1073741824.0, "--memory-limit GIB");
      }
      else if (a == "--force")
        force = true;
      else if (!a.empty() && a[0] == '-')
        throw coupling::InputError("cosim run: unknown option '" + diagnose::clip(a) + "'" +
                                   app::did_you_mean(a, {"--output", "--set", "--restart", "--force"}));
    }
    for (const auto &o : outputs)
    {
      try
      {
        (void)app::check_result_folder(o, force, {sandbox / "work" / "case.prm"});
      }
      catch (const coupling::InputError &e)
      {
        cosim_fuzz::check_message(e);
      }
      if (!o.empty() && o[0] != '/')
        (void)app::check_result_folder((sandbox / "work" / o).string(), force, {sandbox / "work" / "case.prm"});
    }
  }
  catch (const coupling::InputError &e)
  {
    cosim_fuzz::check_message(e);
  }
  // the checks write nothing: the working folder stays empty
  if (!fs::is_empty(sandbox / "work"))
    std::abort();
  return 0;
}
