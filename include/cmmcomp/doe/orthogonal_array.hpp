// SPDX-License-Identifier: MIT
/// @file Orthogonal arrays: Taguchi's standard L9 (3^4), L18 (2x3^7) and L27 (3^13) tables.
///
/// An orthogonal array is a table of runs x columns whose cells are level indices. In this
/// module level indices are **0-based** everywhere (Taguchi's published tables are 1-based:
/// level 1 there is level 0 here). Columns are 0-based too, so a published table's column c2
/// is column 1.
///
/// Offline code (the design of experiments happens before training): it allocates, and it
/// reports invalid arguments with exceptions. Nothing here is RT-safe.
#pragma once

#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::doe {

/// A runs x columns table of 0-based level indices, with the number of levels of each column.
/// Immutable once built; copyable.
class OrthogonalArray {
 public:
  /// Builds an array from its rows of 0-based levels. Setup only.
  /// @param name               label such as "L18", used in messages
  /// @param levels_per_column  number of levels of each column (each >= 2)
  /// @param rows               one row per run; every row has levels_per_column.size() cells,
  ///                           cell c in [0, levels_per_column[c])
  /// @throws ConfigError when there are no runs or no columns, a column has fewer
  ///         than 2 levels, a row has the wrong length, or a cell is out of range.
  /// The constructor does not require orthogonality: use is_orthogonal() to check it.
  OrthogonalArray(std::string name,
                  std::vector<int> levels_per_column,
                  const std::vector<std::vector<int>>& rows);

  /// The label given at construction ("L9", "L18", "L27" for the factories).
  const std::string& name() const noexcept { return name_; }
  /// Number of runs (rows).
  int runs() const noexcept { return runs_; }
  /// Number of columns.
  int columns() const noexcept { return static_cast<int>(levels_.size()); }
  /// Number of levels of `column`. @throws std::out_of_range for a bad column.
  int levels(int column) const {
    check_column(column);
    return levels_[static_cast<std::size_t>(column)];
  }
  /// Number of levels of every column.
  const std::vector<int>& levels_per_column() const noexcept { return levels_; }
  /// 0-based level of cell (`run`, `column`), both 0-based.
  /// @throws std::out_of_range for a bad run or column.
  int level(int run, int column) const {
    check_column(column);
    if (run < 0 || run >= runs_) {
      throw std::out_of_range("OrthogonalArray " + name_ + ": run " + std::to_string(run) +
                              " outside [0, " + std::to_string(runs_) + ")");
    }
    return cells_[static_cast<std::size_t>(run) * levels_.size() +
                  static_cast<std::size_t>(column)];
  }
  /// The levels of one column, one per run. @throws std::out_of_range for a bad column.
  std::vector<int> column(int index) const {
    check_column(index);
    std::vector<int> out;
    out.reserve(static_cast<std::size_t>(runs_));
    for (int r = 0; r < runs_; ++r) out.push_back(level(r, index));
    return out;
  }
  /// A copy of the table as rows (the constructor's input form), e.g. to derive a modified
  /// array.
  std::vector<std::vector<int>> rows() const {
    std::vector<std::vector<int>> out(static_cast<std::size_t>(runs_));
    for (int r = 0; r < runs_; ++r) {
      const auto begin = cells_.begin() +
                         static_cast<std::ptrdiff_t>(static_cast<std::size_t>(r) * levels_.size());
      out[static_cast<std::size_t>(r)].assign(begin,
                                              begin + static_cast<std::ptrdiff_t>(levels_.size()));
    }
    return out;
  }

 private:
  void check_column(int column) const {
    if (column < 0 || column >= columns()) {
      throw std::out_of_range("OrthogonalArray " + name_ + ": column " + std::to_string(column) +
                              " outside [0, " + std::to_string(columns()) + ")");
    }
  }

  std::string name_;
  std::vector<int> levels_;  // levels per column
  std::vector<int> cells_;   // row-major, runs_ x levels_.size()
  int runs_ = 0;
};

namespace detail {

/// Builds an array from a table written 1-based, as published.
OrthogonalArray from_one_based(std::string name,
                               std::vector<int> levels_per_column,
                               std::initializer_list<std::initializer_list<int>> table);

}  // namespace detail

/// Taguchi's standard L9 (3^4): 9 runs, 4 three-level columns. Setup only.
OrthogonalArray taguchi_l9();

/// Taguchi's standard L18 (2^1 x 3^7): 18 runs; column 0 has 2 levels, columns 1..7 have 3.
/// Cell for cell the published table, written 1-based below (its columns c1..c8 are 0..7
/// here). Which factor goes on which column is not part of the array: the project puts PV, PD,
/// AV, AD on c2..c5 and Y on c6, see paper_l18_assignment() in designs.hpp. Setup only.
OrthogonalArray taguchi_l18();

/// Taguchi's standard L27 (3^13): 27 runs, 13 three-level columns. With (a, b, c) the base-3
/// digits of the 0-based run index (a most significant), the columns are, mod 3:
/// a, b, a+b, 2a+b, c, a+c, 2a+c, b+c, a+b+c, 2a+b+c, 2b+c, a+2b+c, 2a+2b+c. Setup only.
OrthogonalArray taguchi_l27();

/// True when every level of `column` appears equally often (runs divisible by its level
/// count). Setup only. @throws std::out_of_range for a bad column.
bool column_is_balanced(const OrthogonalArray& oa, int column);

/// True when the array has strength 2: every column is balanced and, for every pair of
/// columns, each of the levels_i x levels_j level combinations appears equally often.
/// Setup only.
bool is_orthogonal(const OrthogonalArray& oa);

}  // namespace cmmcomp::doe
