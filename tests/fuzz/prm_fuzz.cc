// libFuzzer target for the case-file reader: any .prm text is either a valid case or an
// InputError of one line; nothing else (no crash, no other exception, no sanitizer report).
// The first line of the input, when it starts with "--set ", is used as one override instead.
// Built and run by tools/sanitize (clang++-14 -fsanitize=fuzzer,address,undefined).
#include <app/case_file.h>
#include <coupling/run_case.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
  std::string text(reinterpret_cast<const char *>(data), size);
  std::vector<std::string> overrides;
  if (text.rfind("--set ", 0) == 0)
  {
    const auto eol = text.find('\n');
    overrides.push_back(text.substr(6, eol == std::string::npos ? std::string::npos : eol - 6));
    text = eol == std::string::npos ? std::string() : text.substr(eol + 1);
  }
  static const std::string path = "/tmp/cosim-prm-fuzz-" + std::to_string(getpid()) + ".prm";
  {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
  }
  try
  {
    (void)app::read_case_file(path, overrides);
  }
  catch (const coupling::InputError &e)
  {
    const std::string what = e.what();
    if (what.empty() || what.find('\n') != std::string::npos)
      std::abort(); // the contract: one non-empty line
  }
  return 0;
}
