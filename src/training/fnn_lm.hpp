// SPDX-License-Identifier: MIT
/// @file Stage 3 of train_fnn (docs/training.md, "How the trainer works"): Levenberg–Marquardt
/// refinement of the ridge start on all data at the chosen λ. Private to the trainer.
///
/// Contract: minimises fnn_problem.hpp's cost with Ceres LM (at most options.max_iterations,
/// widths bounded below by min_width, dense normal Cholesky up to 1000 parameters and sparse
/// above, one thread). It runs only when the data hold more design points than the premise
/// has centres and widths; otherwise, or with max_iterations = 0, the start is kept and the
/// summary's message says why. Fills the summary's message, iterations, costs and flags.
#pragma once

#include <ceres/ceres.h>

#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <string>
#include <vector>

#include "ceres_progress.hpp"
#include "fnn_normalise.hpp"
#include "fnn_problem.hpp"

namespace cmmcomp::training::detail {

template <int kInputs, int kSets, int kOutputs>
void refine_lm(const NormalisedData<kInputs, kOutputs>& d,
               const FnnTrainingOptions& options,
               const std::vector<double>& prior,
               std::vector<double>& premise,
               std::vector<double>& consequents,
               TrainingSummary& s) {
  using Layout = fuzzy::TskLayout<kInputs, kSets, kOutputs>;
  constexpr int kPremise = Layout::kConsequentsOffset;
  if (options.max_iterations == 0) {
    s.message = "ridge initialisation only (max_iterations = 0)";
    s.solution_usable = true;
    s.converged = true;
    return;
  }
  if (d.groups <= static_cast<std::size_t>(kPremise)) {
    // The data cannot place the centres and widths, and moving them to fit the few design
    // points bends the network between them (docs/training.md).
    s.message = "ridge initialisation kept: " + std::to_string(d.groups) +
                " design points cannot place the premise's " + std::to_string(kPremise) +
                " centres and widths";
    s.solution_usable = true;
    s.converged = true;
    return;
  }
  ceres::Problem problem;
  std::vector<double*> order;
  build_problem<kInputs, kSets, kOutputs>(d, prior, s.lambda, problem, premise, consequents, order);
  for (int i = 0; i < kInputs; ++i) {
    for (int t = 0; t < kSets; ++t) {
      problem.SetParameterLowerBound(premise.data(), Layout::width_index(i, t), options.min_width);
    }
  }
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  const int params = kPremise + kOutputs * Layout::kConsequentBlock;
  so.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;  // and without a sparse library
  if (params > 1000) {
    for (const auto library : {ceres::SUITE_SPARSE, ceres::EIGEN_SPARSE}) {
      if (ceres::IsSparseLinearAlgebraLibraryTypeAvailable(library)) {
        so.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
        so.sparse_linear_algebra_library_type = library;
        break;
      }
    }
  }
  so.max_num_iterations = options.max_iterations;
  so.num_threads = 1;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  ProgressCallback callback(options.progress);
  so.callbacks.push_back(&callback);
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  s.message = summary.message;
  s.iterations = static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 = start
  s.initial_cost = summary.initial_cost;
  s.final_cost = summary.final_cost;
  s.solution_usable = summary.IsSolutionUsable();
  s.converged = summary.termination_type == ceres::CONVERGENCE;
}

}  // namespace cmmcomp::training::detail
