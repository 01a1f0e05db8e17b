#include <coupling/errors.h>
#include <diagnose/text_input.h>

#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace diagnose
{
  using coupling::InputError;

  namespace
  {
    /// Length of the valid UTF-8 sequence starting at text[i], or 0 when it is not one.
    std::size_t utf8_length(const std::string &text, const std::size_t i)
    {
      const auto byte = [&](std::size_t k) { return static_cast<unsigned char>(text[k]); };
      const unsigned char b = byte(i);
      std::size_t n         = 0;
      unsigned int code     = 0;
      if (b < 0x80)
        return 1;
      if (b >= 0xC2 && b <= 0xDF)
        n = 2, code = b & 0x1Fu;
      else if (b >= 0xE0 && b <= 0xEF)
        n = 3, code = b & 0x0Fu;
      else if (b >= 0xF0 && b <= 0xF4)
        n = 4, code = b & 0x07u;
      else
        return 0;
      if (i + n > text.size())
        return 0;
      for (std::size_t k = 1; k < n; ++k)
      {
        if ((byte(i + k) & 0xC0u) != 0x80u)
          return 0;
        code = (code << 6) | (byte(i + k) & 0x3Fu);
      }
      // overlong forms, surrogates and code points past U+10FFFF are not UTF-8
      if ((n == 3 && code < 0x800) || (n == 4 && (code < 0x10000 || code > 0x10FFFF)) ||
          (code >= 0xD800 && code <= 0xDFFF))
        return 0;
      return n;
    }

    std::string hex_byte(const unsigned char b)
    {
      char buffer[8];
      std::snprintf(buffer, sizeof buffer, "\\x%02X", b);
      return buffer;
    }

    std::size_t line_of(const std::string &text, const std::size_t at)
    {
      std::size_t line = 1;
      for (std::size_t k = 0; k < at && k < text.size(); ++k)
        line += text[k] == '\n';
      return line;
    }
  } // namespace

  std::optional<std::size_t> invalid_utf8_at(const std::string &text)
  {
    for (std::size_t i = 0; i < text.size();)
    {
      const std::size_t n = utf8_length(text, i);
      if (n == 0)
        return i;
      i += n;
    }
    return std::nullopt;
  }

  std::string clip(const std::string &text, const std::size_t limit)
  {
    std::string out;
    std::size_t i = 0;
    for (; i < text.size() && out.size() < limit;)
    {
      const unsigned char b = static_cast<unsigned char>(text[i]);
      if (b == '\n')
        out += "\\n", ++i;
      else if (b == '\t')
        out += ' ', ++i;
      else if (b < 0x20 || b == 0x7F)
        out += hex_byte(b), ++i;
      else
      {
        const std::size_t n = utf8_length(text, i);
        if (n == 0)
          out += hex_byte(b), ++i;
        else
          out.append(text, i, n), i += n;
      }
    }
    if (i < text.size())
      out += "... (" + std::to_string(text.size()) + " bytes)";
    return out;
  }

  std::string normalise_text(const std::string &bytes, const std::string &name)
  {
    const std::string shown = clip(name);
    if (bytes.size() >= 2 && ((bytes[0] == '\xFF' && bytes[1] == '\xFE') || (bytes[0] == '\xFE' && bytes[1] == '\xFF')))
      throw InputError(shown + ":1: the file is UTF-16 (byte-order mark " + hex_byte(bytes[0]) +
                       hex_byte(bytes[1]) + "); save it as UTF-8 or plain ASCII text");
    std::string text;
    text.reserve(bytes.size());
    std::size_t start = 0;
    if (bytes.compare(0, 3, "\xEF\xBB\xBF") == 0)
      start = 3; // UTF-8 byte-order mark: harmless, dropped
    for (std::size_t i = start; i < bytes.size(); ++i)
    {
      const char ch = bytes[i];
      if (ch == '\r')
      {
        text += '\n';
        if (i + 1 < bytes.size() && bytes[i + 1] == '\n')
          ++i;
      }
      else if (ch == '\0')
        throw InputError(shown + ":" + std::to_string(line_of(text, text.size())) +
                         ": a NUL byte; this is not a text file (save it as UTF-8 text)");
      else
        text += ch;
    }
    if (const auto at = invalid_utf8_at(text))
    {
      const std::size_t line_start = text.rfind('\n', *at) == std::string::npos ? 0 : text.rfind('\n', *at) + 1;
      throw InputError(shown + ":" + std::to_string(line_of(text, *at)) + ": byte " +
                       hex_byte(static_cast<unsigned char>(text[*at])) + " at column " +
                       std::to_string(*at - line_start + 1) +
                       " is not UTF-8 (Latin-1 or another encoding?); save the file as UTF-8");
    }
    return text;
  }

  std::string read_text_file(const std::string &path, const std::string &what)
  {
    namespace fs = std::filesystem;
    const std::string shown = clip(path);
    std::error_code ec;
    if (fs::is_directory(path, ec))
      throw InputError(shown + ": is a folder, not a " + what);
    std::ifstream in(path, std::ios::binary);
    if (!in)
      throw InputError(shown + ": cannot open the " + what + " (" + std::strerror(errno) + ")");
    const auto size = fs::file_size(path, ec);
    if (!ec && size > max_text_file_bytes)
      throw InputError(shown + ": " + std::to_string(size) + " bytes is too large for a " + what + " (at most " +
                       std::to_string(max_text_file_bytes >> 20) + " MiB)");
    std::ostringstream bytes;
    bytes << in.rdbuf();
    if (in.bad())
      throw InputError(shown + ": cannot read the " + what);
    return normalise_text(bytes.str(), path);
  }

  bool is_decimal_number(const std::string &text)
  {
    std::size_t i = 0;
    const std::size_t n = text.size();
    if (i < n && (text[i] == '+' || text[i] == '-'))
      ++i;
    std::size_t digits = 0;
    while (i < n && std::isdigit(static_cast<unsigned char>(text[i])))
      ++i, ++digits;
    if (i < n && text[i] == '.')
    {
      ++i;
      while (i < n && std::isdigit(static_cast<unsigned char>(text[i])))
        ++i, ++digits;
    }
    if (digits == 0)
      return false;
    if (i < n && (text[i] == 'e' || text[i] == 'E'))
    {
      ++i;
      if (i < n && (text[i] == '+' || text[i] == '-'))
        ++i;
      std::size_t exponent_digits = 0;
      while (i < n && std::isdigit(static_cast<unsigned char>(text[i])))
        ++i, ++exponent_digits;
      if (exponent_digits == 0)
        return false;
    }
    return i == n;
  }

  std::string escape_prm_value(const std::string &value)
  {
    std::string out;
    for (const char ch : value)
    {
      if (ch == '#')
        out += '\\';
      out += ch;
    }
    return out;
  }
  std::string strip_prm_comment(const std::string &line)
  {
    std::string out;
    for (std::size_t i = 0; i < line.size(); ++i)
    {
      if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '#')
      {
        out += '#';
        ++i;
      }
      else if (line[i] == '#')
        break;
      else
        out += line[i];
    }
    const auto last = out.find_last_not_of(" \t");
    return last == std::string::npos ? std::string() : out.substr(0, last + 1);
  }
} // namespace diagnose
