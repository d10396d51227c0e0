// SPDX-License-Identifier: MIT
/// @file Tests of stage 4 of the trainer (src/training/fnn_gd.hpp): the paper's gradient descent.
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
#include "training/fnn_gd.hpp"

namespace cmmcomp::training {
namespace {

using namespace fnn_test;

// --- The paper's gradient descent ------------------------------------------------------------

TEST(FnnTrainer, GradientDescentBaselineReducesCost) {
  Rng rng{test::seed() + 5};
  Rows<2> x;
  Rows<1> y;
  for (int k = 0; k < 30; ++k) {
    const double a = rng.uniform(0, 1), b = rng.uniform(0, 1);
    x.push_back({a, b});
    y.push_back({std::sin(3 * a) + b});
  }
  FnnTrainingOptions options;
  options.method = FnnMethod::kGradientDescent;
  options.epochs = 150;
  options.goal = 0.0;  // unreachable: runs every epoch
  int calls = 0;
  bool decreasing = true;
  double last = std::numeric_limits<double>::infinity();
  options.progress = [&](int, double cost) {
    ++calls;
    decreasing = decreasing && cost < last;
    last = cost;
  };
  const auto r = train_fnn<2, 3, 1>(x, y, options);
  ASSERT_TRUE(r.summary.usable()) << r.summary.message;
  EXPECT_EQ(r.summary.method, FnnMethod::kGradientDescent);
  EXPECT_EQ(r.summary.iterations, 150);
  EXPECT_FALSE(r.summary.converged);
  EXPECT_EQ(calls, 151);
  // The paper's β = 0.001 is slow but steady: the cost falls at every epoch.
  EXPECT_TRUE(decreasing);
  EXPECT_LT(r.summary.final_cost, 0.75 * r.summary.initial_cost);
  EXPECT_EQ(r.summary.lambda, 0.0);  // the paper has no ridge
}

TEST(FnnTrainer, GradientDescentStopsAtReachableGoal) {
  Rng rng{test::seed() + 6};
  Rows<2> x;
  Rows<1> y;
  for (int k = 0; k < 30; ++k) {
    const double a = rng.uniform(0, 1), b = rng.uniform(0, 1);
    x.push_back({a, b});
    y.push_back({2 * a + b});
  }
  FnnTrainingOptions options;
  options.method = FnnMethod::kGradientDescent;
  options.goal = 0.2;  // normalised MSE; a constant predictor has 1
  options.epochs = 1000;
  options.learning_rate = 0.005;  // faster than the paper's 0.001, to keep the test short
  const auto r = train_fnn<2, 3, 1>(x, y, options);
  ASSERT_TRUE(r.summary.usable()) << r.summary.message;
  EXPECT_TRUE(r.summary.converged) << r.summary.message;
  EXPECT_LT(r.summary.iterations, 1000);
  // Normalised MSE ≤ goal ⇔ raw RMSE ≤ √goal · std.
  double mean = 0, var = 0;
  for (const auto& v : y) mean += v[0] / 30.0;
  for (const auto& v : y) var += (v[0] - mean) * (v[0] - mean) / 30.0;
  EXPECT_LE(r.summary.train_rmse[0], std::sqrt(0.2 * var) * (1 + 1e-9));
}

// --- The stage on its own ---------------------------------------------------------------------

TEST(FnnDescendGd, StartsFromTheSeededRandomModelAndStopsAtTheEpochLimit) {
  Rng rng{test::seed() + 21};
  Rows<2> x;
  Rows<1> y;
  for (int k = 0; k < 30; ++k) {
    x.push_back({rng.uniform(), rng.uniform()});
    y.push_back({x.back()[0] * x.back()[1]});
  }
  FnnTrainingOptions options;
  options.method = FnnMethod::kGradientDescent;
  options.epochs = 0;
  options.goal = 0.0;
  const auto d = detail::normalise<2, 1>(x, y, options);
  using Layout = fuzzy::TskLayout<2, 3, 1>;
  const std::vector<double> prior(static_cast<std::size_t>(Layout::kConsequentBlock), 0.0);
  auto run = [&](std::uint64_t seed) {
    options.seed = seed;
    std::vector<double> premise(static_cast<std::size_t>(Layout::kConsequentsOffset), 0.0);
    std::vector<double> consequents(static_cast<std::size_t>(Layout::kConsequentBlock), 0.0);
    TrainingSummary s;
    detail::descend_gd<2, 3, 1>(d, options, prior, premise, consequents, s);
    EXPECT_EQ(s.iterations, 0);
    EXPECT_EQ(s.message, "epoch limit reached");
    EXPECT_EQ(s.initial_cost, s.final_cost);
    for (int i = 0; i < 2; ++i) {
      for (int t = 0; t < 3; ++t) {
        const double c = premise[static_cast<std::size_t>(Layout::centre_index(i, t))];
        const double w = premise[static_cast<std::size_t>(Layout::width_index(i, t))];
        EXPECT_TRUE(c >= 0.0 && c < 1.0) << c;
        EXPECT_TRUE(w >= 0.25 && w <= 0.75) << w;  // U(0.5, 1.5) × spacing 0.5
      }
    }
    for (const double p : consequents) EXPECT_TRUE(p >= -0.5 && p < 0.5) << p;
    return premise;
  };
  EXPECT_EQ(run(5), run(5));
  EXPECT_NE(run(5), run(6));
}

}  // namespace
}  // namespace cmmcomp::training
