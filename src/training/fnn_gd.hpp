// SPDX-License-Identifier: MIT
/// @file Stage 4 of train_fnn, the alternative to stage 3 (docs/training.md, "How the trainer
/// works"): the paper's training as a baseline. Private to the trainer.
///
/// Contract: replaces the start with the paper's random parameters (SplitMix64 seeded from
/// options.seed; centres U(0, 1), widths U(0.5, 1.5)·spacing, consequents U(−0.5, 0.5)), then
/// full-batch plain gradient descent on fnn_problem.hpp's cost (the gradient from the same Jet
/// code through ceres::Problem::Evaluate), step options.learning_rate, at most options.epochs,
/// stopping when the mean squared error [normalised] is ≤ options.goal; widths are projected
/// onto ≥ min_width after each step. A non-finite cost or gradient stops at the last finite
/// parameters. Fills the summary's message, iterations (epochs), costs and flags.
#pragma once

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstddef>
#include <string>
#include <vector>

#include "fnn_normalise.hpp"
#include "fnn_problem.hpp"

namespace cmmcomp::training::detail {

template <int kInputs, int kSets, int kOutputs>
void descend_gd(const NormalisedData<kInputs, kOutputs>& d,
                const FnnTrainingOptions& options,
                const std::vector<double>& prior,
                std::vector<double>& premise,
                std::vector<double>& consequents,
                TrainingSummary& s) {
  using Layout = fuzzy::TskLayout<kInputs, kSets, kOutputs>;
  constexpr int kPremise = Layout::kConsequentsOffset;
  cmmcomp::detail::SplitMix64 rng{options.seed ^ 0x5DEECE66DULL};
  const double spacing = kSets > 1 ? 1.0 / (kSets - 1) : 1.0;
  for (int i = 0; i < kInputs; ++i) {
    for (int t = 0; t < kSets; ++t) premise[sz(Layout::centre_index(i, t))] = rng.uniform();
    for (int t = 0; t < kSets; ++t) {
      premise[sz(Layout::width_index(i, t))] =
          std::max(rng.uniform(0.5, 1.5) * spacing, options.min_width);
    }
  }
  for (double& p : consequents) p = rng.uniform(-0.5, 0.5);

  ceres::Problem problem;
  std::vector<double*> order;
  build_problem<kInputs, kSets, kOutputs>(d, prior, s.lambda, problem, premise, consequents, order);
  ceres::Problem::EvaluateOptions eo;
  eo.parameter_blocks = order;
  eo.num_threads = 1;
  const std::size_t data_residuals = d.x.size() * static_cast<std::size_t>(kOutputs);
  std::vector<double> residuals, gradient;
  std::vector<double> last_premise = premise, last_consequents = consequents;
  s.solution_usable = true;
  s.message = "epoch limit reached";
  int epoch = 0;
  for (;; ++epoch) {
    double cost = 0;
    const bool evaluated = problem.Evaluate(eo, &cost, &residuals, &gradient, nullptr);
    double sq = 0;
    for (std::size_t r = 0; r < data_residuals && r < residuals.size(); ++r)
      sq += residuals[r] * residuals[r];
    const double mse = sq / static_cast<double>(data_residuals);
    if (!evaluated || !std::isfinite(cost) || !all_finite(gradient)) {
      premise = last_premise;
      consequents = last_consequents;
      s.solution_usable = epoch > 0;
      s.message = "gradient descent: non-finite cost or gradient at epoch " +
                  std::to_string(epoch) + "; stopped at the last finite parameters";
      break;
    }
    if (epoch == 0) s.initial_cost = cost;
    s.final_cost = cost;
    if (options.progress) options.progress(epoch, cost);
    if (mse <= options.goal) {
      s.converged = true;
      s.message = "gradient descent: goal reached (MSE " + std::to_string(mse) +
                  " <= " + std::to_string(options.goal) + ")";
      break;
    }
    if (epoch >= options.epochs) break;
    last_premise = premise;
    last_consequents = consequents;
    for (int k = 0; k < kPremise; ++k) premise[sz(k)] -= options.learning_rate * gradient[sz(k)];
    for (std::size_t k = 0; k < consequents.size(); ++k) {
      consequents[k] -= options.learning_rate * gradient[static_cast<std::size_t>(kPremise) + k];
    }
    for (int i = 0; i < kInputs; ++i) {
      for (int t = 0; t < kSets; ++t) {
        double& w = premise[sz(Layout::width_index(i, t))];
        w = std::max(w, options.min_width);
      }
    }
  }
  s.iterations = epoch;
}

}  // namespace cmmcomp::training::detail
