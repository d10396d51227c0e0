// SPDX-License-Identifier: MIT
/// @file How well a model predicts a test set, as the paper reports it: its Table 5 (mean |error|
/// before and mean |residual| after compensation, reduction, variance after) and its Fig. 5
/// (measured, predicted and residual per test sample), drawn with gnuplot.
///
/// Offline, setup only. cmmcomp-train eval prints and plots these; the accuracy ctest reads the
/// same numbers from its --json output.
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/status.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
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

/// A model on a test set, as cmmcomp-train eval measures it: every row evaluated under the clamp
/// policy, the interval's half-width at the row's inputs, Table 5 and each parameter's coverage.
struct TestSetEvaluation {
  TestSetPredictions predictions;
  std::array<Table5Row, kErrors.size()> table{};
  std::size_t samples = 0;
  std::size_t outside = 0;  ///< rows outside the training ranges (clamped)
  /// Share of rows with |measured − predicted| <= the half-width [%]; NaN without an interval.
  std::array<double, kErrors.size()> coverage_pct{};
};

/// Evaluates `model` (a network of the input set `Inputs`, 4 outputs) with its `interval` on
/// `rows`. Throws Error naming `source` and the row the model cannot evaluate, ConfigError for an
/// empty set.
template <typename Inputs, typename Model>
TestSetEvaluation evaluate_test_set(const Model& model,
                                    const fuzzy::IntervalCalibration<kErrorCount>& interval,
                                    const std::vector<DatasetRow>& rows,
                                    const std::string& source) {
  const auto s = samples<Inputs>(rows);
  TestSetEvaluation e;
  e.samples = rows.size();
  std::array<std::size_t, kErrorCount> covered{};
  for (std::size_t i = 0; i < rows.size(); ++i) {
    std::array<double, kErrorCount> y{};
    const Status st = fuzzy::evaluate(model, s.inputs[i], y, fuzzy::DomainPolicy::kClamp);
    if (!ok(st)) {
      throw Error(source + ": row " + std::to_string(i + 1) + ": the model cannot evaluate it (" +
                  to_string(st) + ")");
    }
    if (st == Status::kOutsideDomain) ++e.outside;
    std::array<double, kErrorCount> u{};
    fuzzy::interval_half_widths_at(interval, model.ranges, s.inputs[i], u);
    for (std::size_t o = 0; o < kErrorCount; ++o) {
      e.predictions.measured[o].push_back(s.targets[i][o]);
      e.predictions.predicted[o].push_back(y[o]);
      e.predictions.half_width[o].push_back(u[o]);
      covered[o] += std::abs(s.targets[i][o] - y[o]) <= u[o] ? 1 : 0;
    }
  }
  e.table = table5(e.predictions);
  for (std::size_t o = 0; o < kErrorCount; ++o) {
    e.coverage_pct[o] = interval.available() ? 100.0 * static_cast<double>(covered[o]) /
                                                   static_cast<double>(rows.size())
                                             : std::nan("");
  }
  return e;
}

/// What a test-set report names besides the evaluation.
struct TestSetReportHeader {
  std::string model_id;
  int inputs = 0;
  std::string data_label;       ///< the test data's name (its path)
  double nominal_coverage = 0;  ///< the model's interval coverage, 0 when it has none
  int format_version = 0;       ///< of the model file
};

/// cmmcomp-train eval's report: Table 5 with the paper's in brackets, the interval's coverage
/// and mean half-width per parameter, and with `check` (not null) the held-out verdict.
std::string format_test_set_report(const TestSetEvaluation& e,
                                   const TestSetReportHeader& header,
                                   const HeldOutCheck* check);
/// The same as JSON text (2-space indent): per parameter (its key) the Table 5 row and the
/// coverage, the nominal coverage, the verdict when checked, the sample counts.
std::string format_test_set_json(const TestSetEvaluation& e,
                                 const TestSetReportHeader& header,
                                 const HeldOutCheck* check);

}  // namespace cmmcomp::training
