#include <diagnose/csv.h>
#include <diagnose/text_input.h>
#include <coupling/run_case.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace diagnose
{
  using coupling::InputError;

  std::string trim(const std::string &text)
  {
    const auto first = text.find_first_not_of(" \t\r\n");
    if (first == std::string::npos)
      return {};
    const auto last = text.find_last_not_of(" \t\r\n");
    return text.substr(first, last - first + 1);
  }

  std::optional<double> parse_finite_double(const std::string &text)
  {
    const std::string t = trim(text);
    if (t.empty() || !is_decimal_number(t))
      return std::nullopt; // hexadecimal, inf, nan: not numbers of a data table or an option
    char *end = nullptr;
    const double value = std::strtod(t.c_str(), &end);
    if (end != t.c_str() + t.size() || !std::isfinite(value))
      return std::nullopt;
    return value;
  }

  namespace
  {
    std::vector<std::string> split_row(const std::string &line, const std::string &where)
    {
      std::vector<std::string> cells;
      std::string cell;
      bool quoted = false;
      for (std::size_t i = 0; i < line.size(); ++i)
      {
        const char ch = line[i];
        if (quoted)
        {
          if (ch == '"' && i + 1 < line.size() && line[i + 1] == '"')
            cell += '"', ++i;
          else if (ch == '"')
            quoted = false;
          else
            cell += ch;
        }
        else if (ch == '"')
          quoted = true;
        else if (ch == ',')
          cells.push_back(trim(cell)), cell.clear();
        else
          cell += ch;
      }
      if (quoted)
        throw InputError(where + ": unterminated quote; a quoted cell must end with \"");
      cells.push_back(trim(cell));
      return cells;
    }
  } // namespace

  CsvTable CsvTable::read(const std::string &path)
  {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec))
      throw InputError(clip(path) + ": cannot open the data file (check the path and Rock/Data directory)");
    std::istringstream in(read_text_file(path, "data file"));
    return parse(in, path);
  }

  CsvTable CsvTable::parse(std::istream &in, const std::string &name)
  {
    CsvTable table;
    table.file_ = clip(name);
    std::ostringstream raw;
    raw << in.rdbuf();
    std::istringstream text(normalise_text(raw.str(), name)); // idempotent after read_text_file
    std::string line;
    std::size_t line_number = 0;
    while (std::getline(text, line))
    {
      ++line_number;
      const std::string where = table.file_ + ":" + std::to_string(line_number);
      const std::string t = trim(line);
      if (t.empty())
        continue;
      if (t[0] == '#')
      {
        if (table.columns_.empty())
          table.comments_.push_back(trim(t.substr(1)));
        continue;
      }
      auto cells = split_row(t, where);
      if (table.columns_.empty())
      {
        for (std::size_t i = 0; i < cells.size(); ++i)
        {
          if (cells[i].empty())
            throw InputError(where + ": header column " + std::to_string(i + 1) +
                             " has no name; the first non-comment line must name every column");
          for (std::size_t j = 0; j < i; ++j)
            if (cells[j] == cells[i])
              throw InputError(where + ": header names column '" + clip(cells[i]) +
                               "' twice; column names must be unique");
        }
        table.columns_ = std::move(cells);
        table.header_line_ = line_number;
        continue;
      }
      if (cells.size() != table.columns_.size())
        throw InputError(where + ": " + std::to_string(cells.size()) + " cells, but the header has " +
                         std::to_string(table.columns_.size()) + " columns (" +
                         std::to_string(table.header_line_) + ": one cell per column, empty allowed)");
      table.rows_.push_back(std::move(cells));
      table.lines_.push_back(line_number);
    }
    if (table.columns_.empty())
      throw InputError(table.file_ + ": no header row; expected '# comment' lines, a header row and data rows");
    return table;
  }

  std::string CsvTable::where(std::size_t row) const
  {
    return file_ + ":" + std::to_string(lines_[row]);
  }

  bool CsvTable::has_column(const std::string &name) const
  {
    for (const auto &c : columns_)
      if (c == name)
        return true;
    return false;
  }

  void CsvTable::require_columns(const std::vector<std::string> &names) const
  {
    for (const auto &n : names)
      if (!has_column(n))
      {
        std::string expected;
        for (const auto &e : names)
          expected += (expected.empty() ? "" : ",") + e;
        throw InputError(file_ + ":" + std::to_string(header_line_) + ": no column '" + clip(n) +
                         "'; the header must contain " + expected);
      }
  }

  std::size_t CsvTable::index(const std::string &column) const
  {
    for (std::size_t i = 0; i < columns_.size(); ++i)
      if (columns_[i] == column)
        return i;
    throw InputError(file_ + ":" + std::to_string(header_line_) + ": no column '" + clip(column) + "'");
  }

  const std::string &CsvTable::text(std::size_t row, const std::string &column) const
  {
    return rows_.at(row)[index(column)];
  }

  std::optional<double> CsvTable::optional_number(std::size_t row, const std::string &column) const
  {
    const std::string &t = text(row, column);
    if (t.empty() || t == "-" || t == "\xE2\x80\x94" || t == "NA")
      return std::nullopt;
    const auto value = parse_finite_double(t);
    if (!value)
      throw InputError(where(row) + ": column " + clip(column) + " = '" + clip(t) +
                       "' is not a finite number (decimal, e.g. 97.07); write a number, or leave the cell empty where unknown");
    return value;
  }

  double CsvTable::number(std::size_t row, const std::string &column) const
  {
    const std::string &t = text(row, column);
    const auto value = parse_finite_double(t);
    if (!value)
      throw InputError(where(row) + ": column " + clip(column) + " = '" + clip(t) +
                       "' is not a finite number (decimal, e.g. 97.07); this column needs a number in every row");
    return *value;
  }
} // namespace diagnose
