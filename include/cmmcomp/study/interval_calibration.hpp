// SPDX-License-Identifier: MIT
/// @file The calibration plot of the prediction interval, measured (docs/uncertainty.md,
/// "Calibration plot"; docs/study.md): nominal against empirical coverage.
///
/// For each nominal coverage c the recipe's network is trained with its interval calibrated at c
/// (as `cmmcomp-train fit --interval-coverage c`), and the share of the recipe's held-out moves
/// (every test seed, pooled) whose measured value lies within predicted ± U_c is measured per
/// parameter. A measurement, not a check: the served 95 % level is checked by interval_coverage.
/// Setup-time code: simulates, trains once per level; throws ConfigError for a level outside
/// (0, 1).
#pragma once

#include <array>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <string>
#include <vector>

namespace cmmcomp::study {

struct IntervalCalibrationRow {
  double nominal_pct = 0;
  std::array<double, kErrorCount> coverage_pct{};
};

struct IntervalCalibrationResult {
  std::string recipe;
  std::size_t test_moves = 0;  ///< pooled over the recipe's test seeds
  std::vector<IntervalCalibrationRow> rows;
};

IntervalCalibrationResult interval_calibration(const Recipe& recipe,
                                               const std::vector<double>& levels,
                                               const RunOptions& options = {});

/// A gnuplot script that draws `result` (nominal against empirical, the diagonal dashed) to
/// `png_path`, the data inline.
std::string interval_calibration_plot(const IntervalCalibrationResult& result,
                                      const std::string& png_path);

}  // namespace cmmcomp::study
