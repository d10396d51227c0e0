// SPDX-License-Identifier: MIT
/// @file The dataset CSV reader and writer.
#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace cmmcomp::io {
namespace {

/// "pv_mm_s,pd_mm,…,rae_um": the header the writer writes.
std::string header_line() {
  std::string s;
  for (const DatasetColumn& c : kDatasetColumns) {
    if (!s.empty()) s += ',';
    s += c.name;
  }
  return s;
}

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return {};
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.emplace_back();
  return cells;
}

/// Why `v` may not stand in column `f`, or an empty string.
std::string range_problem(std::size_t f, double v) {
  const DatasetColumnRange& r = kDatasetColumns[f].range;
  if (!std::isfinite(v)) return "is not finite";
  const bool low = r.min_exclusive ? !(v > r.min) : !(v >= r.min);
  if (!low && v <= r.max) return {};
  return fmt::format("is outside {}{:g} .. {:g}] (docs/dataset-csv.md)",
                     r.min_exclusive ? "(" : "[",
                     r.min,
                     r.max);
}

}  // namespace

std::vector<DatasetRow> parse_dataset_csv(const std::string& text, const std::string& source) {
  // A byte-order mark, as some spreadsheet programs write, is not part of the first column name.
  const bool bom = text.compare(0, 3, "\xEF\xBB\xBF") == 0;
  std::istringstream in(bom ? text.substr(3) : text);
  std::string line;
  int line_no = 0;
  std::vector<int> column_of_field;  // cell index of each schema column
  std::size_t header_cells = 0;
  std::vector<DatasetRow> rows;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string t = trim(line);
    if (t.empty() || t[0] == '#') continue;
    const std::vector<std::string> cells = split(t);
    if (column_of_field.empty()) {
      header_cells = cells.size();
      for (const DatasetColumn& column : kDatasetColumns) {
        int found = -1;
        for (std::size_t i = 0; i < cells.size(); ++i) {
          if (cells[i] == column.name) found = static_cast<int>(i);
        }
        if (found < 0) {
          throw ConfigError(
              fmt::format("{}:{}: missing column '{}' (the header must name all of: {})",
                          source,
                          line_no,
                          column.name,
                          header_line()));
        }
        column_of_field.push_back(found);
      }
      continue;
    }
    if (in.eof()) {  // getline met the end of the text before a line end
      throw ConfigError(fmt::format(
          "{}:{}: the last line has no line end: the file may have been cut inside a cell "
          "(if it is complete, end it with a line break)",
          source,
          line_no));
    }
    if (cells.size() != header_cells) {
      throw ConfigError(fmt::format(
          "{}:{}: {} cells, the header has {}", source, line_no, cells.size(), header_cells));
    }
    DatasetRow row;
    for (std::size_t f = 0; f < kDatasetColumns.size(); ++f) {
      const std::string& cell = cells[static_cast<std::size_t>(column_of_field[f])];
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(cell.c_str(), &end);
      // ERANGE with a finite result is an underflow to a subnormal or zero: a number all the
      // same. An overflow gives ±HUGE_VAL.
      const bool overflow = errno == ERANGE && std::isinf(v);
      if (cell.empty() || end != cell.c_str() + cell.size() || overflow) {
        throw ConfigError(fmt::format("{}:{}: column '{}': '{}' is not a number",
                                      source,
                                      line_no,
                                      kDatasetColumns[f].name,
                                      cell));
      }
      const std::string problem = range_problem(f, v);
      if (!problem.empty()) {
        throw ConfigError(fmt::format("{}:{}: column '{}': '{}' {}",
                                      source,
                                      line_no,
                                      kDatasetColumns[f].name,
                                      cell,
                                      problem));
      }
      row.*(kDatasetColumns[f].field) = v;
    }
    rows.push_back(row);
  }
  if (column_of_field.empty()) throw ConfigError(source + ": empty file (no header)");
  if (rows.empty()) throw ConfigError(source + ": no data rows after the header");
  return rows;
}

std::vector<DatasetRow> read_dataset_csv(const std::string& path) {
  return parse_dataset_csv(read_file_bounded(path, "dataset CSV", kMaxTextFileBytes), path);
}

std::string format_dataset_csv(const std::vector<DatasetRow>& rows) {
  std::string s = header_line();
  s += '\n';
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const DatasetRow& r = rows[i];
    for (std::size_t f = 0; f < kDatasetColumns.size(); ++f) {
      const std::string problem = range_problem(f, r.*(kDatasetColumns[f].field));
      if (!problem.empty()) {
        throw ConfigError(fmt::format("dataset row {}: column '{}': {} {}",
                                      i + 1,
                                      kDatasetColumns[f].name,
                                      r.*(kDatasetColumns[f].field),
                                      problem));
      }
    }
    for (std::size_t f = 0; f < kDatasetColumns.size(); ++f) {
      fmt::format_to(
          std::back_inserter(s), "{}{:.10g}", f ? "," : "", r.*(kDatasetColumns[f].field));
    }
    s += '\n';
  }
  return s;
}

void write_dataset_csv(const std::string& path, const std::vector<DatasetRow>& rows) {
  write_file_atomically(path, format_dataset_csv(rows));
}

TrainingConditions dataset_conditions(const std::vector<DatasetRow>& rows) {
  TrainingConditions c;
  if (rows.empty()) return c;
  ConditionRange pa{rows.front().pa_mm_s2, rows.front().pa_mm_s2};
  ConditionRange aa{rows.front().aa_mm_s2, rows.front().aa_mm_s2};
  for (const DatasetRow& r : rows) {
    pa.lo = std::min(pa.lo, r.pa_mm_s2);
    pa.hi = std::max(pa.hi, r.pa_mm_s2);
    aa.lo = std::min(aa.lo, r.aa_mm_s2);
    aa.hi = std::max(aa.hi, r.aa_mm_s2);
  }
  c.pa_mm_s2 = pa;
  c.aa_mm_s2 = aa;
  return c;
}

}  // namespace cmmcomp::io
