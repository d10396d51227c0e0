// SPDX-License-Identifier: MIT
/// @file Tests of stage 3 of the trainer (src/training/fnn_lm.hpp over fnn_problem.hpp): LM
/// refinement and its residual.
#include <ceres/ceres.h>
#include <ceres/dynamic_autodiff_cost_function.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "fnn_test_support.hpp"
#include "support/test_seed.hpp"
#include "training/fnn_lm.hpp"
#include "training/fnn_problem.hpp"

namespace cmmcomp::training {
namespace {

using namespace fnn_test;

// --- Recovery of a known network -------------------------------------------------------------

TEST(FnnTrainer, RecoversKnownNetwork) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed()};
  // Truth: a 2-input, 3-set, 2-output network on x0 ∈ [10, 200], x1 ∈ [1, 5], premise within
  // ±0.05 of the trainer's initialisation (centres 0, .5, 1; widths .5), random consequents.
  using Model = fuzzy::TskModel<double, 2, 3, 2>;
  Model truth;
  truth.ranges = {fuzzy::InputRange{10, 200}, fuzzy::InputRange{1, 5}};
  for (int i = 0; i < 2; ++i) {
    for (int s = 0; s < 3; ++s) {
      truth.params.centre(i, s) = 0.5 * s + rng.uniform(-0.05, 0.05);
      truth.params.width(i, s) = 0.5 + rng.uniform(-0.05, 0.05);
    }
  }
  for (int o = 0; o < 2; ++o) {
    for (int j = 0; j < Model::kRules; ++j) {
      for (int t = 0; t < 3; ++t) truth.params.consequent(o, j, t) = rng.uniform(-10.0, 10.0);
    }
  }
  // A 9 × 9 grid (corners included, so the data ranges are the true ranges).
  Rows<2> x;
  Rows<2> y;
  for (int a = 0; a < 9; ++a) {
    for (int b = 0; b < 9; ++b) {
      const std::array<double, 2> v{10.0 + 190.0 * a / 8.0, 1.0 + 4.0 * b / 8.0};
      std::array<double, 2> out{};
      ASSERT_EQ(fuzzy::evaluate(truth, v, out, fuzzy::DomainPolicy::kReject), Status::kOk);
      x.push_back(v);
      y.push_back(out);
    }
  }
  FnnTrainingOptions options;
  options.lambda = 1e-9;
  options.max_iterations = 25;
  const auto result = train_fnn<2, 3, 2>(x, y, options);
  ASSERT_TRUE(result.summary.usable()) << result.summary.message;
  EXPECT_DOUBLE_EQ(result.model.ranges[0].lo, 10.0);
  EXPECT_DOUBLE_EQ(result.model.ranges[1].hi, 5.0);
  EXPECT_TRUE(fuzzy::validate(result.model));

  // Predictions at 200 fresh random points: max error below 1 % of the target spread.
  double spread = 0, max_err = 0;
  for (const auto& v : y) spread = std::max({spread, std::abs(v[0]), std::abs(v[1])});
  for (int k = 0; k < 200; ++k) {
    const std::array<double, 2> v{rng.uniform(10, 200), rng.uniform(1, 5)};
    std::array<double, 2> want{}, got{};
    ASSERT_EQ(fuzzy::evaluate(truth, v, want, fuzzy::DomainPolicy::kReject), Status::kOk);
    ASSERT_EQ(fuzzy::evaluate(result.model, v, got, fuzzy::DomainPolicy::kReject), Status::kOk);
    for (std::size_t o = 0; o < 2; ++o) max_err = std::max(max_err, std::abs(want[o] - got[o]));
  }
  EXPECT_LT(max_err, 0.01 * spread) << "spread " << spread << ", " << result.summary.message;
  EXPECT_LT(result.summary.train_rmse[0], 1e-3 * spread);
  EXPECT_LE(result.summary.train_rmse[0], result.summary.init_train_rmse[0]);
}

// --- Jacobian of the residual ----------------------------------------------------------------

template <int kI, int kS>
void check_gradient(std::uint64_t seed) {
  using Residual = detail::FnnSampleResidual<kI, kS>;
  Rng rng{seed};
  std::vector<double> premise(static_cast<std::size_t>(Residual::kPremiseSize));
  for (int i = 0; i < kI; ++i) {
    for (int s = 0; s < kS; ++s) {
      premise[static_cast<std::size_t>(Residual::Layout::centre_index(i, s))] =
          rng.uniform(-0.2, 1.2);
      premise[static_cast<std::size_t>(Residual::Layout::width_index(i, s))] =
          rng.uniform(0.2, 0.8);
    }
  }
  std::vector<std::vector<double>> rules(static_cast<std::size_t>(Residual::kRules),
                                         std::vector<double>(Residual::kTerms));
  for (auto& r : rules)
    for (double& v : r) v = rng.uniform(-2, 2);
  auto* functor = new Residual;
  for (int i = 0; i < kI; ++i) functor->input[static_cast<std::size_t>(i)] = rng.uniform(-0.1, 1.1);
  functor->target = 0.3;
  ceres::DynamicAutoDiffCostFunction<Residual, detail::kFnnJetStride> cost(functor);
  cost.AddParameterBlock(Residual::kPremiseSize);
  for (int j = 0; j < Residual::kRules; ++j) cost.AddParameterBlock(Residual::kTerms);
  cost.SetNumResiduals(1);

  std::vector<double*> blocks{premise.data()};
  for (auto& r : rules) blocks.push_back(r.data());
  std::vector<std::vector<double>> jac(blocks.size());
  std::vector<double*> jac_ptr;
  jac[0].resize(premise.size());
  for (std::size_t b = 1; b < blocks.size(); ++b) jac[b].resize(Residual::kTerms);
  for (auto& j : jac) jac_ptr.push_back(j.data());
  double r0 = 0;
  ASSERT_TRUE(cost.Evaluate(blocks.data(), &r0, jac_ptr.data()));

  // Central differences, h = 1e-6 (truncation O(h²) ≈ 1e-12, rounding ≈ 1e-10): agreement to
  // 1e-7 · max(1, |J|).
  const double h = 1e-6;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    for (std::size_t k = 0; k < jac[b].size(); ++k) {
      const double keep = blocks[b][k];
      double rp = 0, rm = 0;
      blocks[b][k] = keep + h;
      ASSERT_TRUE(cost.Evaluate(blocks.data(), &rp, nullptr));
      blocks[b][k] = keep - h;
      ASSERT_TRUE(cost.Evaluate(blocks.data(), &rm, nullptr));
      blocks[b][k] = keep;
      const double fd = (rp - rm) / (2 * h);
      EXPECT_NEAR(jac[b][k], fd, 1e-7 * std::max(1.0, std::abs(fd))) << "block " << b << " k " << k;
    }
  }
}

TEST(FnnSampleResidual, AutoDiffJacobianMatchesCentralDifferences) {
  SCOPED_TRACE(test::seed_message());
  check_gradient<2, 3>(test::seed());
  check_gradient<4, 3>(test::seed() + 1);  // the paper's network, 429 parameters
}

TEST(FnnSampleResidual, ResidualIsTheRtForwardPass) {
  // The residual equals evaluate() of the same parameters (normalised ranges [0, 1]) − target.
  Rng rng{test::seed() + 7};
  fuzzy::TskModel<double, 2, 3, 1> m;
  for (double& v : m.params.values) v = rng.uniform(0.2, 1.0);
  detail::FnnSampleResidual<2, 3> r;
  r.input = {0.3, 0.8};
  r.target = 0.25;
  std::vector<const double*> blocks{m.params.data()};
  for (int j = 0; j < 9; ++j) blocks.push_back(m.params.data() + 12 + 3 * j);
  double res = 0;
  ASSERT_TRUE(r(blocks.data(), &res));
  std::array<double, 1> y{};
  ASSERT_EQ(fuzzy::evaluate(m, {0.3, 0.8}, y, fuzzy::DomainPolicy::kReject), Status::kOk);
  EXPECT_EQ(res, y[0] - 0.25);
}

TEST(FnnTrainer, LmRefinesOnlyWithMoreDesignPointsThanPremiseParameters) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 37};
  for (const std::size_t points : {std::size_t{24}, std::size_t{25}}) {
    Rows<4> u;
    const Rows<4> distinct = random_inputs4(rng, points, &u);
    Rows<4> x;
    Rows<1> y;
    for (int repeat = 0; repeat < 3; ++repeat) {
      for (std::size_t k = 0; k < points; ++k) {
        x.push_back(distinct[k]);
        y.push_back({smooth4(u[k]) + 0.1 * rng.normal()});
      }
    }
    FnnTrainingOptions options;
    options.interval_coverage = 0;
    const auto result = train_fnn<4, 3, 1>(x, y, options);
    ASSERT_TRUE(result.summary.usable());
    EXPECT_EQ(result.summary.design_points, points);
    // Random inputs are not on three levels: the first-order prior, as before.
    EXPECT_EQ(result.summary.prior, (std::vector<std::string>{"first-order"}));
    if (points <= 24) {
      EXPECT_EQ(result.summary.iterations, 0) << points;
    } else {
      EXPECT_GT(result.summary.iterations, 0) << points;
    }
  }
}

// --- The ridge residual and the stage's guards -------------------------------------------------

TEST(FnnRidgeCost, ResidualAndJacobianAreSqrtLambdaTimesTheDeviation) {
  const std::array<double, 3> prior{1.0, -2.0, 0.5};
  const detail::RidgeCost<3> cost(4.0, prior.data());
  const std::array<double, 3> p{2.0, -2.0, 0.0};
  const double* params[] = {p.data()};
  std::array<double, 3> r{};
  std::array<double, 9> jac{};
  double* jacobians[] = {jac.data()};
  ASSERT_TRUE(cost.Evaluate(params, r.data(), jacobians));
  EXPECT_EQ(r, (std::array<double, 3>{2.0, 0.0, -1.0}));
  EXPECT_EQ(jac, (std::array<double, 9>{2, 0, 0, 0, 2, 0, 0, 0, 2}));
}

TEST(FnnRefineLm, KeepsTheStartWithoutIterationsOrWithTooFewDesignPoints) {
  const Rows<1> x{{0.0}, {0.5}, {1.0}, {0.0}, {0.5}, {1.0}};
  const Rows<1> y{{0.0}, {1.0}, {0.0}, {0.1}, {0.9}, {0.1}};
  FnnTrainingOptions options;
  options.folds = 2;
  const auto d = detail::normalise<1, 1>(x, y, options);
  const std::vector<double> start_premise{0.0, 0.5, 1.0, 0.5, 0.5, 0.5};
  const std::vector<double> start_consequents(6, 0.25);
  const std::vector<double> prior(6, 0.0);
  for (const int iterations : {0, 8}) {
    options.max_iterations = iterations;
    std::vector<double> premise = start_premise, consequents = start_consequents;
    TrainingSummary s;
    detail::refine_lm<1, 3, 1>(d, options, prior, premise, consequents, s);
    EXPECT_EQ(premise, start_premise);
    EXPECT_EQ(consequents, start_consequents);
    EXPECT_TRUE(s.solution_usable);
    EXPECT_NE(s.message.find(iterations == 0 ? "max_iterations = 0" : "3 design points"),
              std::string::npos)
        << s.message;
  }
}

}  // namespace
}  // namespace cmmcomp::training
