// SPDX-License-Identifier: MIT
/// @file The bodies of include/cmmcomp/doe/orthogonal_array.hpp.
#include <cmmcomp/doe/orthogonal_array.hpp>

namespace cmmcomp::doe {

OrthogonalArray::OrthogonalArray(std::string name,
                                 std::vector<int> levels_per_column,
                                 const std::vector<std::vector<int>>& rows)
    : name_(std::move(name)), levels_(std::move(levels_per_column)) {
  if (levels_.empty()) throw ConfigError("OrthogonalArray " + name_ + ": no columns");
  if (rows.empty()) throw ConfigError("OrthogonalArray " + name_ + ": no runs");
  for (std::size_t c = 0; c < levels_.size(); ++c) {
    if (levels_[c] < 2) {
      throw ConfigError("OrthogonalArray " + name_ + ": column " + std::to_string(c) +
                        " has fewer than 2 levels");
    }
  }
  runs_ = static_cast<int>(rows.size());
  cells_.reserve(rows.size() * levels_.size());
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].size() != levels_.size()) {
      throw ConfigError("OrthogonalArray " + name_ + ": run " + std::to_string(r) + " has " +
                        std::to_string(rows[r].size()) + " cells, expected " +
                        std::to_string(levels_.size()));
    }
    for (std::size_t c = 0; c < levels_.size(); ++c) {
      const int v = rows[r][c];
      if (v < 0 || v >= levels_[c]) {
        throw ConfigError("OrthogonalArray " + name_ + ": cell (run " + std::to_string(r) +
                          ", column " + std::to_string(c) + ") = " + std::to_string(v) +
                          " is outside [0, " + std::to_string(levels_[c]) + ")");
      }
      cells_.push_back(v);
    }
  }
}

namespace detail {

OrthogonalArray from_one_based(std::string name,
                               std::vector<int> levels_per_column,
                               std::initializer_list<std::initializer_list<int>> table) {
  std::vector<std::vector<int>> rows;
  rows.reserve(table.size());
  for (const auto& row : table) {
    std::vector<int> r;
    r.reserve(row.size());
    for (const int v : row) r.push_back(v - 1);
    rows.push_back(std::move(r));
  }
  return OrthogonalArray(std::move(name), std::move(levels_per_column), rows);
}

}  // namespace detail

}  // namespace cmmcomp::doe

namespace cmmcomp::doe {

OrthogonalArray taguchi_l9() {
  return detail::from_one_based("L9",
                                {3, 3, 3, 3},
                                {
                                    {1, 1, 1, 1},
                                    {1, 2, 2, 2},
                                    {1, 3, 3, 3},
                                    {2, 1, 2, 3},
                                    {2, 2, 3, 1},
                                    {2, 3, 1, 2},
                                    {3, 1, 3, 2},
                                    {3, 2, 1, 3},
                                    {3, 3, 2, 1},
                                });
}

OrthogonalArray taguchi_l18() {
  return detail::from_one_based("L18",
                                {2, 3, 3, 3, 3, 3, 3, 3},
                                {
                                    {1, 1, 1, 1, 1, 1, 1, 1},
                                    {1, 1, 2, 2, 2, 2, 2, 2},
                                    {1, 1, 3, 3, 3, 3, 3, 3},
                                    {1, 2, 1, 1, 2, 2, 3, 3},
                                    {1, 2, 2, 2, 3, 3, 1, 1},
                                    {1, 2, 3, 3, 1, 1, 2, 2},
                                    {1, 3, 1, 2, 1, 3, 2, 3},
                                    {1, 3, 2, 3, 2, 1, 3, 1},
                                    {1, 3, 3, 1, 3, 2, 1, 2},
                                    {2, 1, 1, 3, 3, 2, 2, 1},
                                    {2, 1, 2, 1, 1, 3, 3, 2},
                                    {2, 1, 3, 2, 2, 1, 1, 3},
                                    {2, 2, 1, 2, 3, 1, 3, 2},
                                    {2, 2, 2, 3, 1, 2, 1, 3},
                                    {2, 2, 3, 1, 2, 3, 2, 1},
                                    {2, 3, 1, 3, 2, 3, 1, 2},
                                    {2, 3, 2, 1, 3, 1, 2, 3},
                                    {2, 3, 3, 2, 1, 2, 3, 1},
                                });
}

OrthogonalArray taguchi_l27() {
  return detail::from_one_based(
      "L27",
      std::vector<int>(13, 3),
      {
          {1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1, 1}, {1, 1, 1, 1, 2, 2, 2, 2, 2, 2, 2, 2, 2},
          {1, 1, 1, 1, 3, 3, 3, 3, 3, 3, 3, 3, 3}, {1, 2, 2, 2, 1, 1, 1, 2, 2, 2, 3, 3, 3},
          {1, 2, 2, 2, 2, 2, 2, 3, 3, 3, 1, 1, 1}, {1, 2, 2, 2, 3, 3, 3, 1, 1, 1, 2, 2, 2},
          {1, 3, 3, 3, 1, 1, 1, 3, 3, 3, 2, 2, 2}, {1, 3, 3, 3, 2, 2, 2, 1, 1, 1, 3, 3, 3},
          {1, 3, 3, 3, 3, 3, 3, 2, 2, 2, 1, 1, 1}, {2, 1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3},
          {2, 1, 2, 3, 2, 3, 1, 2, 3, 1, 2, 3, 1}, {2, 1, 2, 3, 3, 1, 2, 3, 1, 2, 3, 1, 2},
          {2, 2, 3, 1, 1, 2, 3, 2, 3, 1, 3, 1, 2}, {2, 2, 3, 1, 2, 3, 1, 3, 1, 2, 1, 2, 3},
          {2, 2, 3, 1, 3, 1, 2, 1, 2, 3, 2, 3, 1}, {2, 3, 1, 2, 1, 2, 3, 3, 1, 2, 2, 3, 1},
          {2, 3, 1, 2, 2, 3, 1, 1, 2, 3, 3, 1, 2}, {2, 3, 1, 2, 3, 1, 2, 2, 3, 1, 1, 2, 3},
          {3, 1, 3, 2, 1, 3, 2, 1, 3, 2, 1, 3, 2}, {3, 1, 3, 2, 2, 1, 3, 2, 1, 3, 2, 1, 3},
          {3, 1, 3, 2, 3, 2, 1, 3, 2, 1, 3, 2, 1}, {3, 2, 1, 3, 1, 3, 2, 2, 1, 3, 3, 2, 1},
          {3, 2, 1, 3, 2, 1, 3, 3, 2, 1, 1, 3, 2}, {3, 2, 1, 3, 3, 2, 1, 1, 3, 2, 2, 1, 3},
          {3, 3, 2, 1, 1, 3, 2, 3, 2, 1, 2, 1, 3}, {3, 3, 2, 1, 2, 1, 3, 1, 3, 2, 3, 2, 1},
          {3, 3, 2, 1, 3, 2, 1, 2, 1, 3, 1, 3, 2},
      });
}

bool column_is_balanced(const OrthogonalArray& oa, int column) {
  const int levels = oa.levels(column);
  if (oa.runs() % levels != 0) return false;
  std::vector<int> count(static_cast<std::size_t>(levels), 0);
  for (int r = 0; r < oa.runs(); ++r) ++count[static_cast<std::size_t>(oa.level(r, column))];
  for (const int n : count) {
    if (n != oa.runs() / levels) return false;
  }
  return true;
}

bool is_orthogonal(const OrthogonalArray& oa) {
  for (int i = 0; i < oa.columns(); ++i) {
    if (!column_is_balanced(oa, i)) return false;
  }
  for (int i = 0; i < oa.columns(); ++i) {
    for (int j = i + 1; j < oa.columns(); ++j) {
      const int li = oa.levels(i);
      const int lj = oa.levels(j);
      if (oa.runs() % (li * lj) != 0) return false;
      std::vector<int> count(static_cast<std::size_t>(li * lj), 0);
      for (int r = 0; r < oa.runs(); ++r) {
        const int cell = oa.level(r, i) * lj + oa.level(r, j);
        ++count[static_cast<std::size_t>(cell)];
      }
      for (const int n : count) {
        if (n != oa.runs() / (li * lj)) return false;
      }
    }
  }
  return true;
}

}  // namespace cmmcomp::doe
