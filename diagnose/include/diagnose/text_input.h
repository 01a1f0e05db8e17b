#pragma once
/// @file
/// The one place where text from users' files and command lines is made safe to parse and to
/// echo: a UTF-8 byte-order mark is dropped, CRLF and lone CR line ends become LF, NUL bytes and
/// invalid UTF-8 are refused with the file and line; and every piece of input quoted in a message
/// goes through clip() (at most ~200 characters, control and non-UTF-8 bytes shown as \xNN), so
/// that a message stays one short line whatever the input held. Used by the CSV reader (data
/// tables, curve files), the checkpoint and result-folder code and the command line of `cosim`.

#include <cstddef>
#include <optional>
#include <string>

namespace diagnose
{
  /// Longest piece of user input echoed in a message [characters].
  constexpr std::size_t max_echo = 200;

  /// Largest text file read as input [bytes]: data tables and case files are kilobytes; anything
  /// this large is not one of them.
  constexpr std::size_t max_text_file_bytes = 64u << 20;

  /// `text` made printable for a one-line message: control characters, NUL, DEL and bytes that
  /// are not valid UTF-8 written as \xNN (a newline as \n), the result clipped to about
  /// `limit` characters with "... (N bytes)" appended when it was longer.
  std::string clip(const std::string &text, std::size_t limit = max_echo);

  /// Normalises the text of input file `name`: drops a leading UTF-8 byte-order mark, turns CRLF
  /// and lone CR into LF. Throws InputError "name:line: ..." for a NUL byte, for bytes that are
  /// not UTF-8 (UTF-16 and Latin-1 files included, with the encoding to save as) and for a
  /// UTF-16 byte-order mark.
  std::string normalise_text(const std::string &bytes, const std::string &name);

  /// Reads and normalises the text file `path` (normalise_text). InputError when it is missing,
  /// a folder, unreadable or larger than max_text_file_bytes; `what` names the kind of file in
  /// the message ("data file", "case file").
  std::string read_text_file(const std::string &path, const std::string &what);

  /// First index of a byte of `text` that is not part of valid UTF-8, or nothing.
  std::optional<std::size_t> invalid_utf8_at(const std::string &text);

  /// True when `text` is a decimal number as users write them: optional sign, digits with an
  /// optional point, optional exponent. Hexadecimal ("0x1p3"), "inf", "nan" and blanks inside are
  /// not (std::strtod accepts them).
  bool is_decimal_number(const std::string &text);

  /// `value` written for a parameter file: every `#` (which starts a comment there) written as
  /// `\#`, so that a path with `#` survives used_parameters.prm and --restart. deal.II 9.4 does
  /// not read `\#` back by itself: app/src/case_file.cc carries it through the parser.
  std::string escape_prm_value(const std::string &value);

  /// One line of a parameter file without its comment: everything from the first `#` that is
  /// not escaped as `\#`, trailing blanks included, removed; each `\#` turned into `#`.
  std::string strip_prm_comment(const std::string &line);
} // namespace diagnose
