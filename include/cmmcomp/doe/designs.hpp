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
  bool is_valid(std::string* why) const {
    const auto fail = [why](const std::string& reason) {
      if (why != nullptr) *why = reason;
      return false;
    };
    if (factor_names.empty()) return fail("no factors");
    if (values.empty()) return fail("no runs");
    std::set<std::string> names;
    for (const auto& n : factor_names) {
      if (n.empty()) return fail("a factor has an empty name");
      if (!names.insert(n).second) return fail("factor name '" + n + "' used twice");
    }
    const std::size_t nf = factor_names.size();
    for (std::size_t r = 0; r < values.size(); ++r) {
      if (values[r].size() != nf) {
        return fail("run " + std::to_string(r) + " has " + std::to_string(values[r].size()) +
                    " values, expected " + std::to_string(nf));
      }
      for (std::size_t f = 0; f < nf; ++f) {
        if (!std::isfinite(values[r][f])) {
          return fail("run " + std::to_string(r) + ": value of '" + factor_names[f] +
                      "' is not finite");
        }
      }
    }
    if (run_index.size() != values.size()) return fail("run_index size differs from runs");
    for (const int i : run_index) {
      if (i < 0) return fail("negative run_index");
    }
    if (!has_levels) {
      if (!level_indices.empty() || !level_counts.empty()) {
        return fail("level members filled but has_levels is false");
      }
      return true;
    }
    if (level_counts.size() != nf) return fail("level_counts size differs from factors");
    for (std::size_t f = 0; f < nf; ++f) {
      if (level_counts[f] < 1) return fail("factor '" + factor_names[f] + "' has no levels");
    }
    if (level_indices.size() != values.size()) return fail("level_indices size differs from runs");
    for (std::size_t r = 0; r < level_indices.size(); ++r) {
      if (level_indices[r].size() != nf) {
        return fail("run " + std::to_string(r) + " has the wrong number of level indices");
      }
      for (std::size_t f = 0; f < nf; ++f) {
        const int l = level_indices[r][f];
        if (l < 0 || l >= level_counts[f]) {
          return fail("run " + std::to_string(r) + ": level " + std::to_string(l) + " of '" +
                      factor_names[f] + "' outside [0, " + std::to_string(level_counts[f]) + ")");
        }
      }
    }
    return true;
  }

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
inline void require_valid(const Design& design, const char* where) {
  std::string why;
  if (!design.is_valid(&why)) throw ConfigError(std::string(where) + ": " + why);
}

inline void require_factor_ok(const Factor& factor, const char* where) {
  if (factor.name.empty()) throw ConfigError(std::string(where) + ": empty factor name");
  if (factor.levels.empty()) {
    throw ConfigError(std::string(where) + ": factor '" + factor.name + "' has no levels");
  }
  for (const double v : factor.levels) {
    if (!std::isfinite(v)) {
      throw ConfigError(std::string(where) + ": factor '" + factor.name +
                        "' has a non-finite level");
    }
  }
}

inline void require_unique_names(const std::vector<std::string>& names, const char* where) {
  std::set<std::string> seen;
  for (const auto& n : names) {
    if (!seen.insert(n).second) {
      throw ConfigError(std::string(where) + ": factor name '" + n + "' used twice");
    }
  }
}

/// Uniform double in [0, 1) from the top 53 bits of one raw draw. Exact and identical on every
/// standard library, unlike std::uniform_real_distribution.
inline double uniform01(std::mt19937_64& rng) {
  return static_cast<double>(rng() >> 11) * 0x1.0p-53;
}

/// Uniform integer in [0, bound) from raw draws, by rejection (no modulo bias). bound >= 1.
inline std::uint64_t uniform_below(std::mt19937_64& rng, std::uint64_t bound) {
  // Accept r < 2^64 - (2^64 mod bound), a multiple of bound.
  const std::uint64_t rem = (std::numeric_limits<std::uint64_t>::max() % bound + 1) % bound;
  const std::uint64_t max_ok = std::numeric_limits<std::uint64_t>::max() - rem;
  std::uint64_t r = rng();
  while (r > max_ok) r = rng();
  return r % bound;
}

inline std::vector<int> identity_runs(std::size_t n) {
  std::vector<int> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = static_cast<int>(i);
  return out;
}

}  // namespace detail

/// Puts `factors[i]` on column `columns[i]` of `oa`: run r gets level oa.level(r, columns[i])
/// of factor i. The result has levels (has_levels == true) and run_index[r] == r.
/// Setup only.
/// @throws ConfigError when factors and columns differ in size or are empty, a
///         column is out of range or used twice, a factor's level count differs from its
///         column's (the message names the factor), or a factor name is empty, repeated or has
///         non-finite levels.
inline Design assign(const OrthogonalArray& oa,
                     const std::vector<Factor>& factors,
                     const std::vector<int>& columns) {
  constexpr const char* kWhere = "doe::assign";
  if (factors.empty()) throw ConfigError("doe::assign: no factors");
  if (factors.size() != columns.size()) {
    throw ConfigError("doe::assign: " + std::to_string(factors.size()) + " factors but " +
                      std::to_string(columns.size()) + " columns");
  }
  std::set<int> used;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < factors.size(); ++i) {
    const Factor& f = factors[i];
    detail::require_factor_ok(f, kWhere);
    const int c = columns[i];
    if (c < 0 || c >= oa.columns()) {
      throw ConfigError("doe::assign: column " + std::to_string(c) + " for factor '" + f.name +
                        "' is outside [0, " + std::to_string(oa.columns()) + ") of " + oa.name());
    }
    if (!used.insert(c).second) {
      throw ConfigError("doe::assign: column " + std::to_string(c) + " for factor '" + f.name +
                        "' is already used by another factor");
    }
    if (static_cast<int>(f.levels.size()) != oa.levels(c)) {
      throw ConfigError("doe::assign: factor '" + f.name + "' has " +
                        std::to_string(f.levels.size()) + " levels but column " +
                        std::to_string(c) + " of " + oa.name() + " has " +
                        std::to_string(oa.levels(c)));
    }
    names.push_back(f.name);
  }
  detail::require_unique_names(names, kWhere);

  Design d;
  d.factor_names = std::move(names);
  d.has_levels = true;
  for (const Factor& f : factors) d.level_counts.push_back(static_cast<int>(f.levels.size()));
  for (int r = 0; r < oa.runs(); ++r) {
    std::vector<double> row;
    std::vector<int> lev;
    for (std::size_t i = 0; i < factors.size(); ++i) {
      const int l = oa.level(r, columns[i]);
      lev.push_back(l);
      row.push_back(factors[i].levels[static_cast<std::size_t>(l)]);
    }
    d.values.push_back(std::move(row));
    d.level_indices.push_back(std::move(lev));
  }
  d.run_index = detail::identity_runs(d.values.size());
  return d;
}

/// The columns for PV, PD, AV, AD (in that order) in taguchi_l18(): c2..c5, i.e. 0-based
/// columns {1, 2, 3, 4}. The project's choice, not the paper's: c1 has only 2 levels, so the four
/// 3-level factors take the first four 3-level columns (cmmcomp-sim puts Y, when given, on the
/// next free one, c6). Another choice is as orthogonal but gives other runs, hence other
/// datasets and ANOVA figures (docs/training.md).
inline std::vector<int> paper_l18_assignment() { return {1, 2, 3, 4}; }

/// The paper's Table 3 factors in SI units, in the order PV [m/s], PD [m], AV [m/s], AD [m]:
/// PV 40/70/100 mm/s, PD 40/60/80 mm (80 mm is the project's choice for the missing third
/// level), AV 8/12/16 mm/s, AD 5/10/15 mm.
inline std::vector<Factor> paper_table3_factors() {
  std::vector<Factor> factors;
  for (std::size_t f = 0; f < paper::kTable3Levels.size(); ++f) {
    Factor factor{PaperInputs::labels()[f], {}};
    // mm / 1000: the double nearest the SI value, the same bits as the literal (0.040).
    for (const double level : paper::kTable3Levels[f]) factor.levels.push_back(level / 1000.0);
    factors.push_back(std::move(factor));
  }
  return factors;
}

/// The 18-run design of the paper's experiment (L18, Table 3 levels): paper_table3_factors() on
/// taguchi_l18() columns paper_l18_assignment(), the project's column choice, not the paper's.
/// Setup only.
inline Design paper_l18_design() {
  return assign(taguchi_l18(), paper_table3_factors(), paper_l18_assignment());
}

/// Largest run count full_factorial() accepts (a guard against a mistyped level list).
inline constexpr long long kMaxFullFactorialRuns = 10'000'000;

/// Every combination of the factors' levels, the last factor varying fastest (so the first
/// run has every factor at level 0). Has levels; run_index[r] == r. Setup only.
/// @throws ConfigError when there are no factors, a factor has no levels, an empty
///         or repeated name or non-finite levels, or the run count exceeds kMaxFullFactorialRuns.
inline Design full_factorial(const std::vector<Factor>& factors) {
  constexpr const char* kWhere = "doe::full_factorial";
  if (factors.empty()) throw ConfigError("doe::full_factorial: no factors");
  long long total = 1;
  std::vector<std::string> names;
  for (const Factor& f : factors) {
    detail::require_factor_ok(f, kWhere);
    total *= static_cast<long long>(f.levels.size());
    if (total > kMaxFullFactorialRuns) {
      throw ConfigError("doe::full_factorial: more than " + std::to_string(kMaxFullFactorialRuns) +
                        " runs");
    }
    names.push_back(f.name);
  }
  detail::require_unique_names(names, kWhere);

  Design d;
  d.factor_names = std::move(names);
  d.has_levels = true;
  for (const Factor& f : factors) d.level_counts.push_back(static_cast<int>(f.levels.size()));
  std::vector<int> lev(factors.size(), 0);
  for (long long r = 0; r < total; ++r) {
    std::vector<double> row;
    for (std::size_t i = 0; i < factors.size(); ++i) {
      row.push_back(factors[i].levels[static_cast<std::size_t>(lev[i])]);
    }
    d.values.push_back(std::move(row));
    d.level_indices.push_back(lev);
    // Odometer increment, last factor fastest.
    for (std::size_t i = factors.size(); i-- > 0;) {
      if (++lev[i] < d.level_counts[i]) break;
      lev[i] = 0;
    }
  }
  d.run_index = detail::identity_runs(d.values.size());
  return d;
}

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
inline Design latin_hypercube(const std::vector<std::string>& names,
                              const std::vector<double>& lower,
                              const std::vector<double>& upper,
                              int samples,
                              std::uint64_t seed) {
  if (names.empty()) throw ConfigError("doe::latin_hypercube: no factors");
  if (lower.size() != names.size() || upper.size() != names.size()) {
    throw ConfigError("doe::latin_hypercube: names, lower and upper differ in size");
  }
  if (samples < 1) throw ConfigError("doe::latin_hypercube: samples must be >= 1");
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (names[f].empty()) throw ConfigError("doe::latin_hypercube: empty factor name");
    if (!std::isfinite(lower[f]) || !std::isfinite(upper[f]) || lower[f] > upper[f]) {
      throw ConfigError("doe::latin_hypercube: factor '" + names[f] +
                        "' needs finite bounds with lower <= upper");
    }
  }
  detail::require_unique_names(names, "doe::latin_hypercube");

  const auto n = static_cast<std::size_t>(samples);
  Design d;
  d.factor_names = names;
  d.values.assign(n, std::vector<double>(names.size(), 0.0));
  std::mt19937_64 rng(seed);
  std::vector<int> strata(n);
  for (std::size_t f = 0; f < names.size(); ++f) {
    for (std::size_t i = 0; i < n; ++i) strata[i] = static_cast<int>(i);
    for (std::size_t i = n - 1; i > 0; --i) {
      const auto j = static_cast<std::size_t>(detail::uniform_below(rng, i + 1));
      std::swap(strata[i], strata[j]);
    }
    const double width = upper[f] - lower[f];
    for (std::size_t r = 0; r < n; ++r) {
      const double u = detail::uniform01(rng);
      d.values[r][f] = lower[f] + width * ((strata[r] + u) / static_cast<double>(samples));
    }
  }
  d.run_index = detail::identity_runs(n);
  return d;
}

/// Each run of `design` repeated `repeats` times consecutively (run 0 x repeats, then run 1 ...).
/// Every repeat keeps its base run's run_index, so average_replicates() can group them.
/// Setup only. @throws ConfigError for repeats < 1 or an invalid design.
inline Design replicate(const Design& design, int repeats) {
  detail::require_valid(design, "doe::replicate");
  if (repeats < 1) throw ConfigError("doe::replicate: repeats must be >= 1");
  Design d;
  d.factor_names = design.factor_names;
  d.has_levels = design.has_levels;
  d.level_counts = design.level_counts;
  for (std::size_t r = 0; r < design.values.size(); ++r) {
    for (int k = 0; k < repeats; ++k) {
      d.values.push_back(design.values[r]);
      if (design.has_levels) d.level_indices.push_back(design.level_indices[r]);
      d.run_index.push_back(design.run_index[r]);
    }
  }
  return d;
}

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
inline Design design_by_name(const std::string& name,
                             const std::vector<Factor>& factors,
                             int lhs_samples,
                             std::uint64_t seed) {
  auto require_levels = [&factors, &name](std::size_t n) {
    for (const Factor& f : factors) {
      if (f.levels.size() != n) {
        throw ConfigError("design " + name + " needs " + std::to_string(n) +
                          " levels per factor; " + f.name + " has " +
                          std::to_string(f.levels.size()));
      }
    }
  };
  const bool with_y = factors.size() == 5;
  if (name == "l18") {
    require_levels(3);
    std::vector<int> columns = paper_l18_assignment();
    if (with_y) columns.push_back(5);  // c6, the next free 3-level column
    return assign(taguchi_l18(), factors, columns);
  }
  if (with_y && (name == "l9" || name == "l27")) {
    throw ConfigError("design " + name +
                      " has no column for y; use l18, full or lhs with y levels");
  }
  if (name == "l9") {
    require_levels(3);
    return assign(taguchi_l9(), factors, {0, 1, 2, 3});
  }
  if (name == "l27") {
    require_levels(3);
    return assign(taguchi_l27(), factors, {0, 1, 4, 12});
  }
  if (name == "full") return full_factorial(factors);
  if (name == "lhs") {
    std::vector<std::string> names;
    std::vector<double> lo, hi;
    for (const Factor& f : factors) {
      names.push_back(f.name);
      lo.push_back(*std::min_element(f.levels.begin(), f.levels.end()));
      hi.push_back(*std::max_element(f.levels.begin(), f.levels.end()));
    }
    return latin_hypercube(names, lo, hi, lhs_samples, seed);
  }
  throw ConfigError("design must be one of l18, l9, l27, full, lhs (got '" + name + "')");
}

}  // namespace cmmcomp::doe
