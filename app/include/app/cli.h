#pragma once
/// @file
/// Small helpers shared by the `cosim` subcommands: option parsing, name suggestions, messages.

#include <string>
#include <vector>

namespace app
{
  /// Levenshtein distance, case-insensitive.
  std::size_t edit_distance(const std::string &a, const std::string &b);

  /// The candidate closest to `name`, or "" when none is reasonably close.
  std::string nearest_name(const std::string &name, const std::vector<std::string> &candidates);

  /// " (did you mean 'X'?)" or "" when nothing is close.
  std::string did_you_mean(const std::string &name, const std::vector<std::string> &candidates);

  /// Walks a subcommand's arguments; options take "--opt value" or "--opt=value".
  class ArgumentCursor
  {
  public:
    ArgumentCursor(const std::string &command, const std::vector<std::string> &args);
    bool done() const { return i_ >= args_.size(); }
    /// The current argument, and moves on.
    std::string next();
    /// The value of option `option` (just read by next()); InputError when it is missing.
    std::string value(const std::string &option);
    /// A finite number for `option`; InputError naming the option otherwise.
    double number(const std::string &option);
    /// The option name part of "--opt=value" (or the argument itself).
    static std::string option_name(const std::string &argument);

  private:
    std::string command_;
    std::vector<std::string> args_;
    std::size_t i_ = 0;
    std::string pending_value_;
    bool has_pending_value_ = false;
  };
} // namespace app
