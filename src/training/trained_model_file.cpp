// SPDX-License-Identifier: MIT
/// @file The training report (include/cmmcomp/training/trained_model_file.hpp).
#include <fmt/format.h>

#include <cmmcomp/schema.hpp>
#include <cmmcomp/training/trained_model_file.hpp>
#include <string>

namespace cmmcomp::training {

std::string format_training_report(const TrainingSummary& s,
                                   const compensation::IntervalCalibration& interval,
                                   std::size_t samples,
                                   const std::string& data_label,
                                   bool lambda_chosen,
                                   double coverage) {
  std::string out = fmt::format("trained {} on {} samples of {} in {:.2f} s: {}\n",
                                to_string(s.method),
                                samples,
                                data_label,
                                s.wall_seconds,
                                s.message);
  out += fmt::format("lambda {:.3g} ({}), {} iterations, cost {:.6g} -> {:.6g}\n",
                     s.lambda,
                     lambda_chosen ? "chosen by cross-validation" : "fixed",
                     s.iterations,
                     s.initial_cost,
                     s.final_cost);
  out += fmt::format("prior ({} design points):", s.design_points);
  for (std::size_t o = 0; o < s.prior.size() && o < kErrors.size(); ++o) {
    out += fmt::format("{} {} {}", o ? "," : "", kErrors[o].label, s.prior[o]);
  }
  out += "\n";
  // The interval's columns are named by its coverage: U95 at the default 0.95.
  const std::string u_name = fmt::format("U{:g}", 100.0 * coverage);
  out += fmt::format("{:<6} {:>14} {:>14} {:>14} {:>14} {:>12} {:>12} {:>10}\n",
                     "",
                     "init RMSE um",
                     "train RMSE um",
                     "CV RMSE um",
                     u_name + " um",
                     u_name + " gain",
                     "corner gain",
                     u_name + " folds");
  for (std::size_t o = 0; o < kErrors.size(); ++o) {
    out += fmt::format("{:<6} {:>14.4f} {:>14.4f} {:>14.4f} {:>14.4f} {:>12.3f} {:>12.3f} {:>10}\n",
                       kErrors[o].label,
                       s.init_train_rmse[o],
                       s.train_rmse[o],
                       s.cv_rmse[o],
                       interval.half_width[o],
                       interval.extrapolation_gain[o],
                       interval.corner_gain[o],
                       o < s.interval_folds.size() ? to_string(s.interval_folds[o]) : "-");
  }
  return out;
}

}  // namespace cmmcomp::training
