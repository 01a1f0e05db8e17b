// libFuzzer target for the measured-data and material tables: the input, split at the first two
// bytes 0x1E (record separator), becomes material.csv, strength.csv and table3_fitted_parameters.csv
// of a folder read by diagnose::read_data and MaterialTable::read. Any bytes give data or a
// one-line InputError (fuzz_contract.h); nothing else (no crash, no other exception).
// Built and run by tools/sanitize (clang++-14 -fsanitize=fuzzer,address,undefined).
#include "fuzz_contract.h"

#include <diagnose/diagnose.h>
#include <diagnose/material_table.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t *data, std::size_t size)
{
  namespace fs = std::filesystem;
  static const fs::path folder = fs::temp_directory_path() / ("cosim-data-fuzz-" + std::to_string(getpid()));
  fs::create_directories(folder);
  const std::string text(reinterpret_cast<const char *>(data), size);
  std::string parts[3];
  std::size_t start = 0;
  for (int i = 0; i < 3; ++i)
  {
    const auto end = i < 2 ? text.find('\x1E', start) : std::string::npos;
    parts[i]       = start <= text.size() ? text.substr(start, end == std::string::npos ? std::string::npos : end - start) : "";
    start          = end == std::string::npos ? text.size() + 1 : end + 1;
  }
  const char *names[3] = {"material.csv", "strength.csv", "table3_fitted_parameters.csv"};
  for (int i = 0; i < 3; ++i)
    std::ofstream(folder / names[i], std::ios::binary | std::ios::trunc) << parts[i];
  try
  {
    (void)diagnose::read_data(folder.string());
  }
  catch (const coupling::InputError &e)
  {
    cosim_fuzz::check_message(e);
  }
  try
  {
    const auto table = diagnose::MaterialTable::read(folder.string());
    for (const auto &g : table.groups())
      (void)table.find(g.group);
  }
  catch (const coupling::InputError &e)
  {
    cosim_fuzz::check_message(e);
  }
  return 0;
}
