// SPDX-License-Identifier: MIT
/// @file Taguchi-style main-effects ANOVA (Wei et al. 2019, §3, Table 4) and replicate averaging.
///
/// Input: a level-based design (every factor's 0-based level in every run) and one response per
/// run, e.g. the mean of the 3 repeats of each L18 run (average_replicates()). For N runs with
/// responses y_r and grand mean m:
///   - total:  SS_T = sum_r (y_r - m)^2,                      dof_T = N - 1
///   - factor: SS_f = sum_l n_l (mean_l - m)^2,               dof_f = levels_f - 1
///             (n_l runs at level l, mean_l their mean response)
///   - error:  SS_e = SS_T - sum_f SS_f,                      dof_e = dof_T - sum_f dof_f
///   - MS = SS / dof; weight % = SS / SS_T * 100; F_f = MS_f / MS_e.
/// The decomposition is exact only when the factors are mutually orthogonal (each factor
/// balanced, each pair of factors balanced), so anova() checks that and rejects other designs.
///
/// Pooling (Taguchi): a pooled factor's SS and dof are added to the error row; its own row is
/// kept, flagged `pooled`, with its own SS, MS and weight but no F. Weights of the non-pooled
/// factors plus the error row sum to 100 %.
///
/// F conventions (never NaN):
///   - error dof 0 (saturated design, nothing pooled): there is no error estimate; every row
///     has has_f == false and f_value == 0. Pool a factor (options) to get F values.
///   - error dof > 0 but SS_e == 0 (responses fully explained): F = +infinity for factors with
///     MS > 0 and F = 0 for factors with MS == 0; has_f == true.
/// Sums of squares below kAnovaRelativeZero * SS_T are rounding noise and are reported as 0.
///
/// Offline code: allocates, throws ConfigError on bad input. Not RT-safe.
#pragma once

#include <cmath>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <iomanip>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::doe {

/// Sums of squares at or below this fraction of the total SS are treated as exactly 0.
inline constexpr double kAnovaRelativeZero = 1e-10;

/// Pooling choices. Default: no pooling.
struct AnovaOptions {
  /// Pool every factor whose weight [%] is strictly below this value. Default 0 (none).
  double pool_below_percent = 0.0;
  /// Pool these factors by name (each must exist). Default empty.
  std::vector<std::string> pool_factors;
  /// When the error dof is still 0 after the pooling above, pool the non-pooled factor with
  /// the smallest SS (the first such on ties), as Taguchi does for saturated designs.
  /// Default false.
  bool pool_smallest_when_saturated = false;

  /// True when pool_below_percent is finite and in [0, 100]; otherwise writes the reason to
  /// `*why` (when not null).
  bool is_valid(std::string* why) const;
};

/// One row of the ANOVA table.
struct AnovaRow {
  std::string source;           ///< factor name, "error" or "total"
  double sum_of_squares = 0.0;  ///< SS [response unit^2]
  int dof = 0;                  ///< degrees of freedom
  double mean_square = 0.0;     ///< SS / dof (0 when dof == 0)
  double weight_percent = 0.0;  ///< SS / SS_total * 100 [%] (0 when SS_total == 0)
  double f_value = 0.0;         ///< MS / MS_error; may be +inf (see file comment); 0 if !has_f
  bool has_f = false;           ///< f_value is meaningful (non-pooled factor, error dof > 0)
  bool pooled = false;          ///< factor pooled into the error row
};

/// The ANOVA result: one row per factor (design order), the error and total rows.
struct AnovaTable {
  std::vector<AnovaRow> factors;                 ///< one per factor, pooled ones flagged
  AnovaRow error;                                ///< residual plus pooled factors
  AnovaRow total;                                ///< SS_T, N - 1
  double grand_mean = 0.0;                       ///< mean response (0 for the SS-only form)
  std::vector<std::vector<double>> level_means;  ///< [factor][level] mean response (main effects)

  /// The row of the factor called `name`. @throws ConfigError when there is none.
  const AnovaRow& factor(const std::string& name) const {
    for (const auto& row : factors) {
      if (row.source == name) return row;
    }
    throw ConfigError("AnovaTable: no factor named '" + name + "'");
  }
};

/// ANOVA table from already computed sums of squares: `factor_ss[i]` with `factor_dof[i]` for
/// factor `factor_names[i]`, and the total `total_ss` with `total_dof`. The error row is
/// total - sum of factors, then pooling and F follow the rules in the file comment. Useful to
/// re-derive F values from published weights (weights are SS shares, so SS_T = 100 works).
/// Setup only.
/// @throws ConfigError for mismatched sizes, empty/repeated names, a negative or
///         non-finite SS, a dof < 1, total_dof < sum of factor dofs, factor SS exceeding the
///         total beyond rounding, an unknown name in options.pool_factors, or invalid options.
AnovaTable anova_from_sums_of_squares(const std::vector<std::string>& factor_names,
                                      const std::vector<double>& factor_ss,
                                      const std::vector<int>& factor_dof,
                                      double total_ss,
                                      int total_dof,
                                      const AnovaOptions& options = {});

/// Main-effects ANOVA from level indices: `level_indices[r][f]` is the 0-based level of factor
/// f (of `level_counts[f]`) in run r, `responses[r]` the response of run r. The factors must be
/// mutually orthogonal (each balanced, each pair balanced); runs may be replicates (then the
/// repeats add error dof). Setup only.
/// @throws ConfigError for fewer than 2 runs, mismatched sizes, a level out of
///         range, a non-finite response, a non-orthogonal set of factors (named in the message),
///         or the errors of anova_from_sums_of_squares().
AnovaTable anova(const std::vector<std::string>& factor_names,
                 const std::vector<int>& level_counts,
                 const std::vector<std::vector<int>>& level_indices,
                 const std::vector<double>& responses,
                 const AnovaOptions& options = {});

/// Main-effects ANOVA of a level-based design (design.has_levels) with one response per run.
/// Setup only. @throws ConfigError for an invalid design, a design without levels,
///         responses.size() != design.runs(), or any error of the level-index form.
AnovaTable anova(const Design& design,
                 const std::vector<double>& responses,
                 const AnovaOptions& options = {});

/// Result of average_replicates().
struct ReplicateAverage {
  Design design;              ///< one row per distinct run_index, in order of first appearance
  std::vector<double> means;  ///< mean response of each of those runs
  std::vector<int> repeats;   ///< how many rows were averaged into each
};

/// Collapses the repeats of a replicated design (rows sharing a run_index, see replicate())
/// into one row each with the mean response, e.g. the 54 L18 samples into 18 means. Each output
/// row keeps its run_index. Setup only.
/// @throws ConfigError for an invalid design, responses.size() != design.runs(), a
///         non-finite response, or rows with the same run_index but different values/levels.
ReplicateAverage average_replicates(const Design& design, const std::vector<double>& responses);

/// The table as aligned text, one row per factor, then error and total, with the columns
/// source, SS, dof, MS, weight %, F (like the paper's Table 4). F shows "pooled" for pooled
/// factors, "-" where it is not defined and "inf" for +infinity. Setup only.
std::string format_anova_table(const AnovaTable& table, int precision = 4);

}  // namespace cmmcomp::doe
