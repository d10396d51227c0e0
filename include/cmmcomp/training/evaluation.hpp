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
  /// The prediction interval's half-width per sample (empty: the model has none).
  std::array<std::vector<double>, kErrors.size()> half_width;
};

/// Table 5 of each parameter. Throws ConfigError for an empty set or vectors of other lengths.
std::array<Table5Row, kErrors.size()> table5(const TestSetPredictions& p);

/// The check of a model on a held-out campaign of the user's machine (docs/measurement.md,
/// "The held-out check"): each parameter's reduction must reach the paper's Table 5 reduction,
/// and its interval's coverage must lie within ±3 points of the nominal coverage, or within
/// the binomial 2σ band of the sample count when that is wider (60 samples: ±5.6 points at 95 %),
/// so that a small campaign does not fail by chance.
struct HeldOutCheck {
  struct Parameter {
    bool reduction_met = false;
    bool coverage_met = false;
    double reduction_pct = 0, paper_reduction_pct = 0;
    double coverage_pct = 0;  ///< NaN when the model has no interval
  };
  std::array<Parameter, kErrors.size()> parameters{};
  double nominal_coverage_pct = 0;
  double coverage_band_pct = 0;  ///< the ± band used
  bool passed = false;
  std::string
      missed;  ///< e.g. "RPE reduction 87.2 % < 90.8 %; RAE coverage 88.0 % outside 92–98 %"
};
inline constexpr double kCoverageTolerancePct = 3.0;

/// The verdict from a test set's Table 5 and each parameter's measured coverage [%] (NaN: none;
/// a model without an interval fails the coverage check).
HeldOutCheck held_out_check(const std::array<Table5Row, kErrors.size()>& table,
                            const std::array<double, kErrors.size()>& coverage_pct,
                            double nominal_coverage_pct,
                            std::size_t samples);

/// The paper's Fig. 5 for gnuplot: `data` (one line per shown sample: index, then measured,
/// predicted, residual and the interval's half-width (0 without one) of each parameter) and
/// `script`, which reads `data_path` and draws a 2×2 PNG to `png_path`: the prediction with its
/// band ± half-width at `coverage_pct` when there is one, titled with `model_id`, the legend
/// below the plots. At most 50 samples, spread evenly over the set (deterministic).
struct Fig5Plot {
  std::string data;
  std::string script;
};
Fig5Plot fig5_plot(const TestSetPredictions& p,
                   const std::string& data_path,
                   const std::string& png_path,
                   const std::string& model_id = "",
                   double coverage_pct = 0);

}  // namespace cmmcomp::training
