// SPDX-License-Identifier: MIT
/// @file A small CSV reader for the measurement files (plan.csv, the recordings): a header row
/// of names, then rows of cells, '#' comment lines and blank lines skipped. Every error names the
/// source and the line. Private to cmmcomp::measure.
#pragma once

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cstdlib>
#include <string>
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

inline std::string trim_cell(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

inline std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (char ch : line) {
    if (ch == ',') {
      cells.push_back(trim_cell(cell));
      cell.clear();
    } else {
      cell += ch;
    }
  }
  cells.push_back(trim_cell(cell));
  return cells;
}

/// Parses `text`; every row must have the header's number of cells.
inline CsvTable parse_csv(const std::string& text, const std::string& source) {
  CsvTable t;
  t.source = source;
  std::size_t pos = 0;
  int line = 0;
  while (pos <= text.size()) {
    std::size_t end = text.find('\n', pos);
    if (end == std::string::npos) end = text.size();
    const std::string raw = text.substr(pos, end - pos);
    pos = end + 1;
    ++line;
    const std::string s = trim_cell(raw);
    if (s.empty() || s[0] == '#') continue;
    std::vector<std::string> cells = split_cells(s);
    if (t.header.empty()) {
      t.header = std::move(cells);
      t.header_line = line;
      continue;
    }
    if (cells.size() != t.header.size()) {
      throw ConfigError(source + ":" + std::to_string(line) + ": " + std::to_string(cells.size()) +
                        " cells, the header has " + std::to_string(t.header.size()));
    }
    t.rows.push_back(std::move(cells));
    t.lines.push_back(line);
  }
  if (t.header.empty()) throw ConfigError(source + ": empty (no header row)");
  return t;
}

}  // namespace cmmcomp::measure::detail
