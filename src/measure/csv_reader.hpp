// SPDX-License-Identifier: MIT
/// @file A small CSV reader for the measurement files (plan.csv, the recordings): a header row
/// of names, then rows of cells, '#' comment lines and blank lines skipped. Every error names the
/// source and the line. Private to cmmcomp::measure.
///
/// The remedies the dataset CSV reader has, for files from other programs: a UTF-8 byte-order
/// mark is not part of the first name; a NUL byte (a binary or corrupt file) is an error naming
/// its line, never a message cut short; a column named twice is an error (neither copy wins
/// quietly); a last line without a line end is an error (the file may have been cut inside its
/// last number). Recordings are read by `read_numeric`, which parses the columns it needs as it
/// splits each line and keeps only doubles: a recording costs 8 bytes a needed cell.
#pragma once

#include <cerrno>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

namespace cmmcomp::measure::detail {

struct CsvTable {
  std::string source;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<int> lines;  ///< the 1-based line of each row

  /// Index of column `name`, or -1.
  int find(const std::string& name) const {
    for (std::size_t i = 0; i < header.size(); ++i) {
      if (header[i] == name) return static_cast<int>(i);
    }
    return -1;
  }
  /// Index of column `name`; ConfigError naming the file when it is missing.
  std::size_t require(const std::string& name) const {
    const int i = find(name);
    if (i < 0)
      throw ConfigError(source + ":" + std::to_string(header_line) + ": no column '" + name + "'");
    return static_cast<std::size_t>(i);
  }
  /// Cell (row r, column c) as a finite number; ConfigError "source:line: column 'x': ...".
  double number(std::size_t r, std::size_t c) const {
    const std::string& cell = rows[r][c];
    char* end = nullptr;
    const double v = std::strtod(cell.c_str(), &end);
    if (cell.empty() || end != cell.c_str() + cell.size() || !std::isfinite(v)) {
      throw ConfigError(where(r) + ": column '" + header[c] + "': '" + cell +
                        "' is not a finite number");
    }
    return v;
  }
  std::string where(std::size_t r) const { return source + ":" + std::to_string(lines[r]); }

  int header_line = 0;
};

inline std::string trim_cell(std::string_view s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string_view::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return std::string(s.substr(b, e - b + 1));
}

inline std::vector<std::string> split_cells(std::string_view line) {
  std::vector<std::string> cells;
  std::size_t pos = 0;
  while (true) {
    const std::size_t comma = line.find(',', pos);
    if (comma == std::string_view::npos) {
      cells.push_back(trim_cell(line.substr(pos)));
      return cells;
    }
    cells.push_back(trim_cell(line.substr(pos, comma - pos)));
    pos = comma + 1;
  }
}

/// Walks the lines of a measurement file: strips a BOM, refuses a NUL byte and a last line
/// without a line end, skips blank and '#' lines. `each(line_no, text)` is called for every
/// other line, the header first.
template <typename Each>
void for_each_line(std::string_view text, const std::string& source, Each&& each) {
  if (text.substr(0, 3) == "\xEF\xBB\xBF") text.remove_prefix(3);
  const std::size_t nul = text.find('\0');
  if (nul != std::string_view::npos) {
    int line = 1;
    for (std::size_t i = 0; i < nul; ++i) line += text[i] == '\n';
    throw ConfigError(source + ":" + std::to_string(line) + ": a NUL byte at offset " +
                      std::to_string(nul) + ": not a text file (binary or corrupt)");
  }
  std::size_t pos = 0;
  int line = 0;
  while (pos < text.size()) {
    std::size_t end = text.find('\n', pos);
    const bool last_without_end = end == std::string_view::npos;
    if (last_without_end) end = text.size();
    const std::string_view raw = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    const std::size_t first = raw.find_first_not_of(" \t\r");
    if (first == std::string_view::npos || raw[first] == '#') continue;
    if (last_without_end) {
      throw ConfigError(source + ":" + std::to_string(line) +
                        ": the last line has no line end: the file may have been cut inside a "
                        "cell (if it is complete, end it with a line break)");
    }
    each(line, raw);
  }
}

/// The header's names; ConfigError when a name is empty or given twice.
inline std::vector<std::string> header_cells(std::string_view raw,
                                             const std::string& source,
                                             int line) {
  std::vector<std::string> names = split_cells(raw);
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (names[i] == names[j]) {
        throw ConfigError(source + ":" + std::to_string(line) + ": column '" + names[i] +
                          "' is named twice (columns " + std::to_string(j + 1) + " and " +
                          std::to_string(i + 1) + ")");
      }
    }
  }
  return names;
}

/// Parses `text`; every row must have the header's number of cells.
inline CsvTable parse_csv(const std::string& text, const std::string& source) {
  CsvTable t;
  t.source = source;
  for_each_line(text, source, [&](int line, std::string_view raw) {
    if (t.header.empty()) {
      t.header = header_cells(raw, source, line);
      t.header_line = line;
      return;
    }
    std::vector<std::string> cells = split_cells(raw);
    if (cells.size() != t.header.size()) {
      throw ConfigError(source + ":" + std::to_string(line) + ": " + std::to_string(cells.size()) +
                        " cells, the header has " + std::to_string(t.header.size()));
    }
    t.rows.push_back(std::move(cells));
    t.lines.push_back(line);
  });
  if (t.header.empty()) throw ConfigError(source + ": empty (no header row)");
  return t;
}

/// The columns of a recording as numbers.
struct NumericColumns {
  std::vector<std::vector<double>> columns;  ///< one per requested name (empty when absent)
  std::vector<bool> present;                 ///< whether each requested column is in the file
  std::vector<int> lines;                    ///< the 1-based line of each row
  std::size_t rows = 0;
};

/// Reads the columns `required` (ConfigError when one is missing) and `optional` of `text`,
/// parsing each needed cell as its line is split; other columns are only counted. The result's
/// columns are `required` then `optional`, in order.
inline NumericColumns read_numeric(std::string_view text,
                                   const std::string& source,
                                   const std::vector<std::string>& required,
                                   const std::vector<std::string>& optional = {}) {
  NumericColumns out;
  const std::size_t wanted = required.size() + optional.size();
  out.columns.resize(wanted);
  out.present.assign(wanted, false);
  std::vector<int> target;  // for each cell of a row: the wanted column it fills, or -1
  std::size_t cells = 0;
  bool have_header = false;
  for_each_line(text, source, [&](int line, std::string_view raw) {
    if (!have_header) {
      const std::vector<std::string> names = header_cells(raw, source, line);
      cells = names.size();
      target.assign(cells, -1);
      for (std::size_t w = 0; w < wanted; ++w) {
        const std::string& name = w < required.size() ? required[w] : optional[w - required.size()];
        for (std::size_t i = 0; i < names.size(); ++i) {
          if (names[i] == name) {
            target[i] = static_cast<int>(w);
            out.present[w] = true;
          }
        }
        if (!out.present[w] && w < required.size()) {
          throw ConfigError(source + ":" + std::to_string(line) + ": no column '" + name + "'");
        }
      }
      have_header = true;
      return;
    }
    std::size_t cell = 0, pos = 0;
    while (true) {
      const std::size_t comma = raw.find(',', pos);
      const std::size_t end = comma == std::string_view::npos ? raw.size() : comma;
      if (cell < cells && target[cell] >= 0) {
        const std::string s = trim_cell(raw.substr(pos, end - pos));
        char* stop = nullptr;
        errno = 0;
        const double v = std::strtod(s.c_str(), &stop);
        if (s.empty() || stop != s.c_str() + s.size() || !std::isfinite(v)) {
          const std::size_t w = static_cast<std::size_t>(target[cell]);
          const std::string& name =
              w < required.size() ? required[w] : optional[w - required.size()];
          throw ConfigError(source + ":" + std::to_string(line) + ": column '" + name + "': '" + s +
                            "' is not a finite number");
        }
        out.columns[static_cast<std::size_t>(target[cell])].push_back(v);
      }
      ++cell;
      if (comma == std::string_view::npos) break;
      pos = comma + 1;
    }
    if (cell != cells) {
      throw ConfigError(source + ":" + std::to_string(line) + ": " + std::to_string(cell) +
                        " cells, the header has " + std::to_string(cells));
    }
    ++out.rows;
    out.lines.push_back(line);
  });
  if (!have_header) throw ConfigError(source + ": empty (no header row)");
  return out;
}

}  // namespace cmmcomp::measure::detail
