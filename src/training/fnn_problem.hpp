// SPDX-License-Identifier: MIT
/// @file The Ceres problem the trainer's refinements minimise (stages 3 and 4 of train_fnn,
/// docs/training.md, "How the trainer works"). Private to the trainer.
///
/// Contract: cost ½Σ_n,o (ŷ_o(x_n) − z_no)² + ½λ Σ (p − p₀)² in normalised units, p every
/// consequent, p₀ the prior. The residual of sample n and output o is FnnSampleResidual, which
/// runs the RT forward pass (TskEvaluator) on ceres::Jet (exact Jacobians): output o of a
/// kOutputs network is the single-output network of the shared premise and consequent block o.
/// Parameter blocks: the premise (centres then widths, 2·kInputs·kSets values) shared by all
/// outputs, then one block of kInputs + 1 consequents per output and rule, so the ridge
/// residuals √λ·(p − p₀) have a block-diagonal Jacobian.
#pragma once

#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstddef>
#include <vector>

#include "fnn_normalise.hpp"

namespace cmmcomp::training::detail {

/// Jet stride of the DynamicAutoDiffCostFunction (derivatives computed per pass).
inline constexpr int kFnnJetStride = 64;

/// The residual of one sample for one output, ŷ(x) − z, evaluated by the RT forward pass.
/// Parameter blocks: block 0 = the premise (layout as tsk_params.hpp), blocks 1…kRules = the
/// kInputs + 1 consequents of rule j − 1 for this output. One residual.
template <int kInputs, int kSets>
struct FnnSampleResidual {
  using Layout = fuzzy::TskLayout<kInputs, kSets, 1>;
  static constexpr int kPremiseSize = Layout::kConsequentsOffset;  ///< 2·kInputs·kSets
  static constexpr int kRules = Layout::kRules;
  static constexpr int kTerms = Layout::kTerms;

  std::array<double, kInputs> input{};  ///< normalised inputs of the sample
  double target = 0;                    ///< normalised target of this output

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    using Net = fuzzy::TskEvaluator<T, kInputs, kSets, 1>;
    // The flat layout forward() reads; heap (std::vector) because it holds 429 Jets for the
    // paper's network, reused per thread to keep allocation out of the Jacobian loop.
    thread_local std::vector<T> params;
    params.resize(static_cast<std::size_t>(Layout::kParamCount));
    for (int k = 0; k < kPremiseSize; ++k) params[static_cast<std::size_t>(k)] = blocks[0][k];
    for (int j = 0; j < kRules; ++j) {
      for (int t = 0; t < kTerms; ++t) {
        params[static_cast<std::size_t>(Layout::consequent_index(0, j, t))] = blocks[1 + j][t];
      }
    }
    typename Net::Input x;
    for (int i = 0; i < kInputs; ++i)
      x[static_cast<std::size_t>(i)] = T(input[static_cast<std::size_t>(i)]);
    typename Net::Output y;
    Net::forward(params.data(), x, y);  // the RT code
    residual[0] = y[0] - T(target);
    return true;
  }
};

/// √λ·(p − p₀) for the kTerms consequents of one rule, p₀ the prior's: linear, Jacobian √λ·I.
template <int kTerms>
class RidgeCost final : public ceres::SizedCostFunction<kTerms, kTerms> {
 public:
  RidgeCost(double lambda, const double* prior) : s_(std::sqrt(lambda)) {
    for (int t = 0; t < kTerms; ++t) prior_[static_cast<std::size_t>(t)] = prior[t];
  }
  bool Evaluate(double const* const* parameters,
                double* residuals,
                double** jacobians) const override {
    for (int t = 0; t < kTerms; ++t) {
      residuals[t] = s_ * (parameters[0][t] - prior_[static_cast<std::size_t>(t)]);
    }
    if (jacobians != nullptr && jacobians[0] != nullptr) {
      for (int r = 0; r < kTerms; ++r) {
        for (int c = 0; c < kTerms; ++c) jacobians[0][r * kTerms + c] = (r == c) ? s_ : 0.0;
      }
    }
    return true;
  }

 private:
  double s_;
  std::array<double, static_cast<std::size_t>(kTerms)> prior_{};
};

/// Adds the residual blocks to `problem`: one per sample and output (FnnSampleResidual), then,
/// when λ > 0, one ridge block per rule and output towards `prior` (rule-major per output, as
/// `consequents`). Blocks point into `premise` and `consequents`, which must outlive the
/// problem; `order` receives the parameter blocks in that order (premise, then consequents).
template <int kInputs, int kSets, int kOutputs>
void build_problem(const NormalisedData<kInputs, kOutputs>& d,
                   const std::vector<double>& prior,
                   double lambda,
                   ceres::Problem& problem,
                   std::vector<double>& premise,
                   std::vector<double>& consequents,
                   std::vector<double*>& order) {
  using Residual = FnnSampleResidual<kInputs, kSets>;
  using Layout = fuzzy::TskLayout<kInputs, kSets, kOutputs>;
  constexpr int kRules = Layout::kRules;
  constexpr int kTerms = Layout::kTerms;
  order.clear();
  order.push_back(premise.data());
  for (int b = 0; b < kOutputs * kRules; ++b)
    order.push_back(consequents.data() + std::ptrdiff_t{b} * kTerms);
  std::vector<double*> blocks(static_cast<std::size_t>(kRules + 1));
  for (int o = 0; o < kOutputs; ++o) {
    blocks[0] = premise.data();
    for (int j = 0; j < kRules; ++j) {
      blocks[sz(j + 1)] = consequents.data() + std::ptrdiff_t{o * kRules + j} * kTerms;
    }
    for (std::size_t k = 0; k < d.x.size(); ++k) {
      auto* functor = new Residual;
      functor->input = d.x[k];
      functor->target = d.z(static_cast<Index>(k), o);
      auto* cost = new ceres::DynamicAutoDiffCostFunction<Residual, kFnnJetStride>(functor);
      cost->AddParameterBlock(Layout::kConsequentsOffset);
      for (int j = 0; j < kRules; ++j) cost->AddParameterBlock(kTerms);
      cost->SetNumResiduals(1);
      problem.AddResidualBlock(cost, nullptr, blocks);
    }
  }
  if (lambda > 0.0) {
    for (int b = 0; b < kOutputs * kRules; ++b) {
      const double* p0 = prior.data() + std::ptrdiff_t{b} * kTerms;
      problem.AddResidualBlock(new RidgeCost<kTerms>(lambda, p0),
                               nullptr,
                               consequents.data() + std::ptrdiff_t{b} * kTerms);
    }
  }
}

}  // namespace cmmcomp::training::detail
