// SPDX-License-Identifier: MIT
/// @file How well a model predicts a test set, as the paper reports it: its Table 5 (mean |error|
/// before and mean |residual| after compensation, reduction, variance after) and its Fig. 5
/// (measured, predicted and residual per test sample), drawn with gnuplot.
///
/// Offline, setup only. cmmcomp-train eval prints and plots these; the accuracy ctest reads the
/// same numbers from its --json output.
#pragma once

#include <array>
#include <cmmcomp/schema.hpp>
#include <string>
#include <vector>

namespace cmmcomp::training {

/// Table 5 of one error parameter on a test set [µm, µm², %].
struct Table5Row {
  double mean_before = 0;    ///< mean |measured|: the error without compensation
  double mean_after = 0;     ///< mean |measured − predicted|: the residual after it
  double reduction_pct = 0;  ///< 100·(before − after)/before
  double var_after = 0;      ///< population variance of the residual
  double max_abs = 0;        ///< largest |residual|
};

/// Measured and predicted values of the four error parameters (kErrors order) on a test set.
struct TestSetPredictions {
  std::array<std::vector<double>, kErrors.size()> measured;
  std::array<std::vector<double>, kErrors.size()> predicted;
};

/// Table 5 of each parameter. Throws ConfigError for an empty set or vectors of other lengths.
std::array<Table5Row, kErrors.size()> table5(const TestSetPredictions& p);

/// The paper's Fig. 5 for gnuplot: `data` (one line per shown sample: index, then measured,
/// predicted and residual of each parameter) and `script`, which reads `data_path` and draws a
/// 2×2 PNG to `png_path`. At most 50 samples, spread evenly over the set (deterministic).
struct Fig5Plot {
  std::string data;
  std::string script;
};
Fig5Plot fig5_plot(const TestSetPredictions& p,
                   const std::string& data_path,
                   const std::string& png_path);

}  // namespace cmmcomp::training
