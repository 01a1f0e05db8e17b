// libFuzzer target for the CSV reader: any byte string is either a table or an
// InputError naming a line; nothing else (no crash, no other exception, no sanitizer report).
// Built and run by tools/sanitize (clang++-14 -fsanitize=fuzzer,address,undefined).
#include <diagnose/csv.h>
#include <coupling/run_case.h>

#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
  const std::string text(reinterpret_cast<const char *>(data), size);
  std::istringstream in(text);
  try
  {
    const diagnose::CsvTable t = diagnose::CsvTable::parse(in, "fuzz.csv");
    // every cell of every row: text, number or a one-line InputError
    for (std::size_t r = 0; r < t.n_rows(); ++r)
    {
      (void)t.where(r);
      for (const auto &c : t.columns())
      {
        (void)t.text(r, c);
        try
        {
          (void)t.optional_number(r, c);
          (void)t.number(r, c);
        }
        catch (const coupling::InputError &)
        {}
      }
    }
  }
  catch (const coupling::InputError &e)
  {
    if (std::string(e.what()).find('\n') != std::string::npos)
      std::abort(); // the contract: one line
  }
  return 0;
}
