#pragma once
/// @file
/// Reading a case file (.prm in deal.II ParameterHandler syntax, or .json as deal.II writes and
/// reads it) into CaseParameters: every key declared with its section, type and default beside
/// the member it sets (app/src/*_keys.cc); `--set "Section/Key=value"` overrides; type, range and
/// physical-consistency checks; the rock group looked up in the data tables. Every mistake is an
/// InputError whose one-line message names the file and line (or the --set argument), the key,
/// what is wrong and what is accepted. deal.II stays inside app/src.

#include <coupling/case_parameters.h>

#include <string>
#include <vector>

namespace app
{
  /// A case, read and checked.
  struct CaseFile
  {
    coupling::CaseParameters parameters;         ///< validated, SI units
    std::string used_parameters;       ///< final values in .prm format (used_parameters.prm)
    std::vector<std::string> warnings; ///< accepted but doubtful settings, one line each
  };

  /// Reads `path` (.json: JSON, else .prm), applies `overrides` ("Section/Key=value", in order) and validates.
  /// Throws InputError. The case name defaults to the file's stem.
  CaseFile read_case_file(const std::string &path, const std::vector<std::string> &overrides);

  /// Every key: "Section/Key [default]: documentation", one per line, for `cosim run --help`.
  std::string case_file_keys_help();

  /// A complete case file of the defaults: every key with its default and documentation, after
  /// a first comment line with the program's version and commit (`cosim run --print-parameters`).
  std::string default_case_file();
} // namespace app
