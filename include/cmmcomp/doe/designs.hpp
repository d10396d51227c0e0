// SPDX-License-Identifier: MIT
/// @file Experimental designs: factors on orthogonal-array columns, full factorial, Latin
/// hypercube, and replication of runs.
///
/// A Design is a plain table: one row of factor values per run. Level-based designs (from an
/// orthogonal array or a full factorial) also carry the 0-based level index of every factor in
/// every run, which is what the main-effects ANOVA (anova.hpp) works on. Values are in the
/// caller's units; paper_table3_factors() gives the paper's levels in SI units.
///
/// Offline code: everything here allocates and throws ConfigError with a readable
/// reason on bad input. Nothing here is RT-safe.
#pragma once

#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/orthogonal_array.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/schema.hpp>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::doe {

/// One factor of an experiment and its levels (in the caller's units; SI in this project).
struct Factor {
  std::string name;            ///< label, unique within a design (e.g. "PV")
  std::vector<double> levels;  ///< value of each level, level 0 first
};

/// The runs of an experiment. Row r of every per-run member describes run r.
struct Design {
  std::vector<std::string> factor_names;    ///< one per factor, unique
  std::vector<std::vector<double>> values;  ///< [run][factor] factor value
  bool has_levels = false;                  ///< level_indices and level_counts are filled
  std::vector<std::vector<int>>
      level_indices;              ///< [run][factor] 0-based level; empty if !has_levels
  std::vector<int> level_counts;  ///< levels of each factor; empty if !has_levels
  /// [run] index of the base run this row is a repeat of. For a design straight from a factory
  /// run_index[r] == r; replicate() copies the base run's index to each repeat, so
  /// average_replicates() (anova.hpp) can group repeats back.
  std::vector<int> run_index;

  /// Number of runs (rows).
  int runs() const noexcept { return static_cast<int>(values.size()); }
  /// Number of factors.
  int factors() const noexcept { return static_cast<int>(factor_names.size()); }

  /// Value of `factor` in `run`. @throws std::out_of_range for a bad index.
  double value(int run, int factor) const {
    check_cell(run, factor);
    return values[static_cast<std::size_t>(run)][static_cast<std::size_t>(factor)];
  }
  /// 0-based level of `factor` in `run`.
  /// @throws std::out_of_range for a bad index, std::logic_error when !has_levels.
  int level(int run, int factor) const {
    if (!has_levels) throw std::logic_error("Design::level: the design has no level indices");
    check_cell(run, factor);
    return level_indices[static_cast<std::size_t>(run)][static_cast<std::size_t>(factor)];
  }
  /// Index of the factor called `name`, or −1 when there is none.
  int find_factor(const std::string& name) const noexcept {
    for (std::size_t f = 0; f < factor_names.size(); ++f) {
      if (factor_names[f] == name) return static_cast<int>(f);
    }
    return -1;
  }
  /// Index of the factor called `name`. @throws ConfigError when there is none.
  int factor_index(const std::string& name) const {
    const int f = find_factor(name);
    if (f < 0) throw ConfigError("Design: no factor named '" + name + "'");
    return f;
  }

  /// Checks the table's consistency: at least one factor and one run, unique non-empty names,
  /// rectangular finite values, run_index of the right size and non-negative, and, when
  /// has_levels, level indices inside [0, level_counts[f]) (otherwise both level members
  /// empty). On failure writes the reason to `*why` (when not null) and returns false.
  bool is_valid(std::string* why) const;

 private:
  void check_cell(int run, int factor) const {
    if (run < 0 || run >= runs() || factor < 0 || factor >= factors()) {
      throw std::out_of_range("Design: cell (run " + std::to_string(run) + ", factor " +
                              std::to_string(factor) + ") outside " + std::to_string(runs()) +
                              " x " + std::to_string(factors()));
    }
  }
};

namespace detail {

/// Throws ConfigError("<where>: <reason>") unless design.is_valid().
void require_valid(const Design& design, const char* where);

void require_factor_ok(const Factor& factor, const char* where);

void require_unique_names(const std::vector<std::string>& names, const char* where);

/// Uniform double in [0, 1) from the top 53 bits of one raw draw. Exact and identical on every
/// standard library, unlike std::uniform_real_distribution.
double uniform01(std::mt19937_64& rng);

/// Uniform integer in [0, bound) from raw draws, by rejection (no modulo bias). bound >= 1.
std::uint64_t uniform_below(std::mt19937_64& rng, std::uint64_t bound);

std::vector<int> identity_runs(std::size_t n);

}  // namespace detail

/// Puts `factors[i]` on column `columns[i]` of `oa`: run r gets level oa.level(r, columns[i])
/// of factor i. The result has levels (has_levels == true) and run_index[r] == r.
/// Setup only.
/// @throws ConfigError when factors and columns differ in size or are empty, a
///         column is out of range or used twice, a factor's level count differs from its
///         column's (the message names the factor), or a factor name is empty, repeated or has
///         non-finite levels.
Design assign(const OrthogonalArray& oa,
              const std::vector<Factor>& factors,
              const std::vector<int>& columns);

/// The columns for PV, PD, AV, AD (in that order) in taguchi_l18(): c2..c5, i.e. 0-based
/// columns {1, 2, 3, 4}. The project's choice, not the paper's: c1 has only 2 levels, so the four
/// 3-level factors take the first four 3-level columns (cmmcomp-sim puts Y, when given, on the
/// next free one, c6). Another choice is as orthogonal but gives other runs, hence other
/// datasets and ANOVA figures (docs/training.md).
std::vector<int> paper_l18_assignment();

/// The paper's Table 3 factors in SI units, in the order PV [m/s], PD [m], AV [m/s], AD [m]:
/// PV 40/70/100 mm/s, PD 40/60/80 mm (80 mm is the project's choice for the missing third
/// level), AV 8/12/16 mm/s, AD 5/10/15 mm.
std::vector<Factor> paper_table3_factors();

/// The 18-run design of the paper's experiment (L18, Table 3 levels): paper_table3_factors() on
/// taguchi_l18() columns paper_l18_assignment(), the project's column choice, not the paper's.
/// Setup only.
Design paper_l18_design();

/// Largest run count full_factorial() accepts (a guard against a mistyped level list).
inline constexpr long long kMaxFullFactorialRuns = 10'000'000;

/// Every combination of the factors' levels, the last factor varying fastest (so the first
/// run has every factor at level 0). Has levels; run_index[r] == r. Setup only.
/// @throws ConfigError when there are no factors, a factor has no levels, an empty
///         or repeated name or non-finite levels, or the run count exceeds kMaxFullFactorialRuns.
Design full_factorial(const std::vector<Factor>& factors);

/// Latin hypercube sample of `samples` runs over the box [lower[f], upper[f]] of each factor.
/// Each factor's range is split into `samples` equal strata and every stratum holds exactly one
/// run; the strata are permuted independently per factor and the point is placed uniformly
/// inside its stratum. No level indices (has_levels == false); run_index[r] == r. Setup only.
///
/// Deterministic for a seed and identical across standard libraries (up to a last-bit
/// difference where a compiler contracts the final expression into an FMA): the generator is
/// std::mt19937_64(seed), and all draws are made here from its raw output, in this order: for
/// each factor f in turn, first a Fisher-Yates shuffle of the strata 0..samples-1 (for
/// i = samples-1 down to 1, swap i with a uniform index in [0, i], drawn by rejection), then one
/// uniform u in [0, 1) (top 53 bits of a draw) per run r; run r gets
/// lower + (upper - lower) * (stratum_r + u_r) / samples.
/// @throws ConfigError when names, lower and upper differ in size or are empty, a
///         name is empty or repeated, a bound is not finite, lower > upper, or samples < 1.
Design latin_hypercube(const std::vector<std::string>& names,
                       const std::vector<double>& lower,
                       const std::vector<double>& upper,
                       int samples,
                       std::uint64_t seed);

/// Each run of `design` repeated `repeats` times consecutively (run 0 x repeats, then run 1 ...).
/// Every repeat keeps its base run's run_index, so average_replicates() can group them.
/// Setup only. @throws ConfigError for repeats < 1 or an invalid design.
Design replicate(const Design& design, int repeats);

/// The designs `cmmcomp-sim dataset --design NAME` knows, on `factors` in the order PV, PD, AV,
/// AD and, optionally, Y (docs/training.md, "The designs: which factor on which column"):
///  - "l18": taguchi_l18() on paper_l18_assignment() (c2..c5), Y on c6, the next free 3-level
///    column; 3 levels per factor;
///  - "l9": taguchi_l9() on c1..c4, "l27": taguchi_l27() on c1, c2, c5, c13 (no column for Y);
///  - "full": every combination of the levels;
///  - "lhs": latin_hypercube() of `lhs_samples` runs between each factor's lowest and highest
///    level, from `seed`.
/// Setup only. Throws ConfigError "design NAME ..." for an unknown name, a factor without the
/// levels the design needs, or Y on a design without a column for it.
Design design_by_name(const std::string& name,
                      const std::vector<Factor>& factors,
                      int lhs_samples,
                      std::uint64_t seed);

}  // namespace cmmcomp::doe
