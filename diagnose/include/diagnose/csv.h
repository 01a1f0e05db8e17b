#pragma once
/// @file
/// A small CSV reader for the data tables in cases/data: `#` comment lines, one header row, then
/// data rows of comma-separated cells. Every error names the file and line (an InputError).

#include <cstddef>
#include <istream>
#include <optional>
#include <string>
#include <vector>

namespace diagnose
{
  /// A read CSV table. Cells are kept as trimmed text; numbers are converted on access, so each
  /// conversion error can name the file, line and column.
  class CsvTable
  {
  public:
    /// Reads `path`. Throws InputError if it cannot be opened or is malformed.
    static CsvTable read(const std::string &path);

    /// Parses `in`; `name` is the file name used in messages.
    static CsvTable parse(std::istream &in, const std::string &name);

    /// File name as given to read() / parse().
    const std::string &file() const { return file_; }
    /// Comment lines before the header, without the leading '#' and blank.
    const std::vector<std::string> &comments() const { return comments_; }
    /// Column names of the header row.
    const std::vector<std::string> &columns() const { return columns_; }
    /// Number of data rows.
    std::size_t n_rows() const { return rows_.size(); }
    /// 1-based line number of data row `row` in the file.
    std::size_t line(std::size_t row) const { return lines_[row]; }
    /// "file:line" of data row `row`, for messages.
    std::string where(std::size_t row) const;

    /// True when the header has column `name`.
    bool has_column(const std::string &name) const;
    /// Throws InputError (naming the header line) unless all `names` are columns.
    void require_columns(const std::vector<std::string> &names) const;

    /// The trimmed text of a cell.
    const std::string &text(std::size_t row, const std::string &column) const;
    /// A required finite number. Throws InputError for an empty, non-numeric or non-finite cell.
    double number(std::size_t row, const std::string &column) const;
    /// A finite number or nothing for an empty cell (also "-", "—", "NA").
    std::optional<double> optional_number(std::size_t row, const std::string &column) const;

  private:
    std::size_t index(const std::string &column) const;

    std::string file_;
    std::size_t header_line_ = 0;
    std::vector<std::string> comments_;
    std::vector<std::string> columns_;
    std::vector<std::vector<std::string>> rows_;
    std::vector<std::size_t> lines_;
  };

  /// Parses a whole string as a finite double; nothing when it is not one.
  std::optional<double> parse_finite_double(const std::string &text);

  /// Removes leading and trailing blanks (spaces, tabs, CR).
  std::string trim(const std::string &text);
} // namespace diagnose
