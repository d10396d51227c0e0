// SPDX-License-Identifier: MIT
/// @file train_fnn as a pipeline of its stages (docs/training.md, "How the trainer works"):
/// fnn_normalise.hpp, fnn_ridge.hpp (with fnn_prior.hpp), fnn_lm.hpp or fnn_gd.hpp over
/// fnn_problem.hpp, and fnn_interval.hpp.
#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "fnn_gd.hpp"
#include "fnn_interval.hpp"
#include "fnn_lm.hpp"
#include "fnn_normalise.hpp"
#include "fnn_ridge.hpp"

namespace cmmcomp::training {

/// The split-conformal quantile of `scores` at coverage `c`: the ⌈(n + 1)c⌉-th smallest (the
/// largest when that exceeds n: too few samples for the coverage, which then is not guaranteed).
double conformal_quantile(std::vector<double> scores, double c) {
  if (scores.empty()) return 0.0;
  std::sort(scores.begin(), scores.end());
  const double n = static_cast<double>(scores.size());
  const auto rank = static_cast<std::size_t>(std::ceil((n + 1.0) * c));
  return scores[std::min(std::max<std::size_t>(rank, 1), scores.size()) - 1];
}

const char* to_string(FnnMethod method) noexcept {
  switch (method) {
    case FnnMethod::kLevenbergMarquardt:
      return "levenberg-marquardt";
    case FnnMethod::kGradientDescent:
      return "gradient-descent";
  }
  return "unknown";
}

const char* to_string(IntervalFolds folds) noexcept {
  switch (folds) {
    case IntervalFolds::kRidge:
      return "ridge";
    case IntervalFolds::kAsServed:
      return "as-served";
    case IntervalFolds::kNarrower:
      return "narrower";
  }
  return "unknown";
}

std::string interval_method(const std::vector<IntervalFolds>& used,
                            const std::vector<std::string>& outputs) {
  std::string which;
  for (std::size_t o = 0; o < used.size(); ++o) {
    if (o > 0) which += ", ";
    which += (o < outputs.size() ? outputs[o] : "output " + std::to_string(o)) + " " +
             to_string(used[o]);
  }
  return "split-conformal on design-point-grouped CV residuals (" + which +
         "); extrapolation gain from held-out ends";
}

IntervalFolds parse_interval_folds(const std::string& text) {
  for (const IntervalFolds f :
       {IntervalFolds::kRidge, IntervalFolds::kAsServed, IntervalFolds::kNarrower}) {
    if (text == to_string(f)) return f;
  }
  throw ConfigError("interval folds '" + text + "': ridge, as-served or narrower");
}

std::string interval_method(const std::vector<IntervalFolds>& used) {
  std::vector<std::string> outputs;
  outputs.reserve(kErrors.size());
  for (const auto& e : kErrors) outputs.emplace_back(e.label);
  return interval_method(used, outputs);
}

bool FnnTrainingOptions::is_valid(std::string* why) const {
  auto fail = [why](const std::string& msg) {
    if (why != nullptr) *why = msg;
    return false;
  };
  if (method != FnnMethod::kLevenbergMarquardt && method != FnnMethod::kGradientDescent) {
    return fail("method is not a FnnMethod value");
  }
  if (folds < 2) return fail("folds must be >= 2");
  if (std::isnan(lambda) || std::isinf(lambda))
    return fail("lambda must be finite (< 0: choose by CV)");
  if (lambda < 0.0) {
    if (lambda_grid.empty()) return fail("lambda_grid is empty (needed when lambda < 0)");
    for (double l : lambda_grid) {
      if (!(l >= 0.0) || !std::isfinite(l))
        return fail("lambda_grid values must be finite and >= 0");
    }
  }
  if (max_iterations < 0) return fail("max_iterations must be >= 0");
  if (!(min_width > 0.0) || !std::isfinite(min_width))
    return fail("min_width must be > 0 and finite");
  if (!(learning_rate > 0.0) || !std::isfinite(learning_rate)) {
    return fail("learning_rate must be > 0 and finite");
  }
  if (epochs < 0) return fail("epochs must be >= 0");
  if (!(goal >= 0.0) || !std::isfinite(goal)) return fail("goal must be >= 0 and finite");
  if (!(interval_coverage == 0.0 || (interval_coverage > 0.0 && interval_coverage < 1.0))) {
    return fail("interval_coverage must be 0 (no interval) or in (0, 1)");
  }
  if (interval_folds != IntervalFolds::kRidge && interval_folds != IntervalFolds::kAsServed &&
      interval_folds != IntervalFolds::kNarrower) {
    return fail("interval_folds is not an IntervalFolds value");
  }
  return true;
}

bool TrainingSummary::usable() const {
  if (!solution_usable || train_rmse.empty()) return false;
  return detail::all_finite(train_rmse);
}

template <int kInputs, int kSets, int kOutputs>
FnnTrainingResult<kInputs, kSets, kOutputs> train_fnn(
    const std::vector<std::array<double, kInputs>>& inputs,
    const std::vector<std::array<double, kOutputs>>& targets,
    const FnnTrainingOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  FnnTrainingResult<kInputs, kSets, kOutputs> result;
  TrainingSummary& s = result.summary;
  s.method = options.method;

  // 1. Check and normalise; 2. the prior, λ by CV and the ridge start.
  const auto data = detail::normalise<kInputs, kOutputs>(inputs, targets, options);
  const detail::RidgeFit<kInputs, kSets, kOutputs> fit(data, options);
  detail::RidgeStart ridge = fit.start(s);
  const auto init = data.template model<kSets>(ridge.premise, ridge.consequents);
  s.init_train_rmse = data.rmse(init);

  // 3. LM refinement, or 4. the paper's gradient descent from random parameters.
  std::vector<double>& premise = ridge.premise;
  std::vector<double>& consequents = ridge.consequents;
  if (options.method == FnnMethod::kLevenbergMarquardt) {
    detail::refine_lm<kInputs, kSets, kOutputs>(
        data, options, ridge.prior, premise, consequents, s);
  } else {
    if (options.lambda <= 0.0) s.lambda = 0.0;
    detail::descend_gd<kInputs, kSets, kOutputs>(
        data, options, ridge.prior, premise, consequents, s);
  }
  result.model = data.template model<kSets>(premise, consequents);
  if (!(detail::all_finite(premise) && detail::all_finite(consequents)) ||
      !fuzzy::validate(result.model)) {
    result.model = init;
    s.solution_usable = false;
    s.message += " (parameters not usable: returned the ridge initialisation)";
  }
  s.train_rmse = data.rmse(result.model);

  // 5. The prediction interval.
  detail::calibrate_interval(fit, ridge.phi, ridge.u, s.lambda, result.interval, s);
  s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

template FnnTrainingResult<5, 3, 4> train_fnn<5, 3, 4>(const std::vector<std::array<double, 5>>&,
                                                       const std::vector<std::array<double, 4>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<4, 3, 4> train_fnn<4, 3, 4>(const std::vector<std::array<double, 4>>&,
                                                       const std::vector<std::array<double, 4>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<4, 3, 1> train_fnn<4, 3, 1>(const std::vector<std::array<double, 4>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<1, 3, 1> train_fnn<1, 3, 1>(const std::vector<std::array<double, 1>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<1, 3, 2> train_fnn<1, 3, 2>(const std::vector<std::array<double, 1>>&,
                                                       const std::vector<std::array<double, 2>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<2, 3, 1> train_fnn<2, 3, 1>(const std::vector<std::array<double, 2>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<2, 3, 2> train_fnn<2, 3, 2>(const std::vector<std::array<double, 2>>&,
                                                       const std::vector<std::array<double, 2>>&,
                                                       const FnnTrainingOptions&);
template FnnTrainingResult<2, 2, 1> train_fnn<2, 2, 1>(const std::vector<std::array<double, 2>>&,
                                                       const std::vector<std::array<double, 1>>&,
                                                       const FnnTrainingOptions&);

}  // namespace cmmcomp::training
