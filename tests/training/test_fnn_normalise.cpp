// SPDX-License-Identifier: MIT
/// @file Tests of stage 1 of the trainer (src/training/fnn_normalise.hpp): checks and
/// normalisation.
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
#include "training/fnn_normalise.hpp"

namespace cmmcomp::training {
namespace {

using namespace fnn_test;

// --- Errors ----------------------------------------------------------------------------------

TEST(FnnTrainer, RejectsFewerSamplesThanFolds) {
  const Rows<2> x = line_inputs(4);
  const Rows<1> y(4, {1.0});
  const std::string m = message_of([&] { train_fnn<2, 3, 1>(x, y); });
  EXPECT_NE(m.find("4 samples are fewer than the 5 cross-validation folds"), std::string::npos)
      << m;
}

TEST(FnnTrainer, RejectsNonFiniteData) {
  const Rows<2> x = line_inputs(10);
  Rows<1> y(10, {1.0});
  y[3][0] = std::numeric_limits<double>::quiet_NaN();
  std::string m = message_of([&] { train_fnn<2, 3, 1>(x, y); });
  EXPECT_NE(m.find("sample 3: target 0 is not finite"), std::string::npos) << m;
  Rows<2> xi = line_inputs(10);
  xi[5][1] = std::numeric_limits<double>::infinity();
  const Rows<1> y1(10, {1.0});
  m = message_of([&] { train_fnn<2, 3, 1>(xi, y1); });
  EXPECT_NE(m.find("sample 5: input 1 is not finite"), std::string::npos) << m;
}

TEST(FnnTrainer, RejectsDegenerateInputNamingIt) {
  Rows<4> x(10, {1.0, 2.0, 3.0, 4.0});
  for (int k = 0; k < 10; ++k) {
    x[static_cast<std::size_t>(k)][0] = k;
    x[static_cast<std::size_t>(k)][1] = k * 2.0;
    x[static_cast<std::size_t>(k)][3] = k + 0.5;
  }
  const Rows<1> y(10, {1.0});
  FnnTrainingOptions options;
  options.input_names = input_labels<PaperInputs>();
  const std::string m = message_of([&] { train_fnn<4, 3, 1>(x, y, options); });
  EXPECT_NE(m.find("input 'AV' is constant"), std::string::npos) << m;
  options.input_names.clear();
  const std::string m2 = message_of([&] { train_fnn<4, 3, 1>(x, y, options); });
  EXPECT_NE(m2.find("input 2 is constant"), std::string::npos) << m2;
}

TEST(FnnTrainer, RejectsEmptyAndMismatchedData) {
  EXPECT_NE(message_of([] { train_fnn<2, 3, 1>({}, {}); }).find("no samples"), std::string::npos);
  const Rows<2> x = line_inputs(10);
  const Rows<1> y(9, {1.0});
  EXPECT_NE(message_of([&] { train_fnn<2, 3, 1>(x, y); }).find("10 input rows but 9 target rows"),
            std::string::npos);
}

TEST(FnnTrainingOptions, ValidatesEveryField) {
  std::string why;
  EXPECT_TRUE(FnnTrainingOptions{}.is_valid(&why)) << why;
  const auto invalid = [](const std::function<void(FnnTrainingOptions&)>& change) {
    FnnTrainingOptions o;
    change(o);
    std::string w;
    const bool valid = o.is_valid(&w);
    return !valid && !w.empty();
  };
  EXPECT_TRUE(invalid([](auto& o) { o.folds = 1; }));
  EXPECT_TRUE(invalid([](auto& o) { o.lambda = std::numeric_limits<double>::quiet_NaN(); }));
  EXPECT_TRUE(invalid([](auto& o) { o.lambda_grid.clear(); }));
  EXPECT_TRUE(invalid([](auto& o) { o.lambda_grid = {1e-3, -1.0}; }));
  EXPECT_TRUE(invalid([](auto& o) { o.max_iterations = -1; }));
  EXPECT_TRUE(invalid([](auto& o) { o.min_width = 0.0; }));
  EXPECT_TRUE(invalid([](auto& o) { o.learning_rate = 0.0; }));
  EXPECT_TRUE(invalid([](auto& o) { o.epochs = -1; }));
  EXPECT_TRUE(invalid([](auto& o) { o.goal = -0.1; }));
  EXPECT_TRUE(invalid([](auto& o) { o.method = static_cast<FnnMethod>(7); }));
  FnnTrainingOptions fixed;
  fixed.lambda = 0.1;
  fixed.lambda_grid.clear();  // not needed with a fixed λ
  EXPECT_TRUE(fixed.is_valid(nullptr));

  FnnTrainingOptions bad;
  bad.folds = 0;
  const Rows<2> x = line_inputs(10);
  const Rows<1> y(10, {1.0});
  EXPECT_NE(message_of([&] { train_fnn<2, 3, 1>(x, y, bad); }).find("FNN training options: folds"),
            std::string::npos);
}

// --- Normalisation and its inverse ------------------------------------------------------------

TEST(FnnNormalise, MapsInputsOntoTheUnitBoxAndTargetsToZScores) {
  const Rows<2> x{{1.0, 10.0}, {3.0, 30.0}, {2.0, 20.0}, {3.0, 30.0}, {1.0, 40.0}};
  const Rows<1> y{{2.0}, {4.0}, {6.0}, {8.0}, {10.0}};
  const auto d = detail::normalise<2, 1>(x, y, FnnTrainingOptions{});
  EXPECT_EQ(d.ranges[0].lo, 1.0);
  EXPECT_EQ(d.ranges[0].hi, 3.0);
  EXPECT_EQ(d.ranges[1].hi, 40.0);
  EXPECT_EQ(d.x[2][0], 0.5);
  EXPECT_EQ(d.x[4][1], 1.0);
  EXPECT_DOUBLE_EQ(d.mean[0], 6.0);
  EXPECT_DOUBLE_EQ(d.scale[0], std::sqrt(8.0));  // population std of 2, 4, 6, 8, 10
  double sum = 0, sq = 0;
  for (int k = 0; k < 5; ++k) {
    sum += d.z(k, 0);
    sq += d.z(k, 0) * d.z(k, 0);
  }
  EXPECT_NEAR(sum, 0.0, 1e-12);
  EXPECT_NEAR(sq / 5.0, 1.0, 1e-12);
  // Samples 1 and 3 share their inputs: one design point of four.
  EXPECT_EQ(d.groups, 4u);
  EXPECT_EQ(d.group[1], d.group[3]);
  EXPECT_NE(d.group[0], d.group[1]);
  EXPECT_EQ(d.xm(2, 0), d.x[2][0]);
}

TEST(FnnNormalise, AConstantOutputKeepsUnitScale) {
  const Rows<1> x{{0.0}, {1.0}, {2.0}, {3.0}, {4.0}};
  const Rows<1> y(5, {7.5});
  const auto d = detail::normalise<1, 1>(x, y, FnnTrainingOptions{});
  EXPECT_EQ(d.scale[0], 1.0);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(d.z(k, 0), 0.0);
}

TEST(FnnNormalise, TheModelInRawUnitsIsTheNormalisedNetworkScaledBack) {
  Rng rng{test::seed() + 3};
  const Rows<2> x = [&] {
    Rows<2> r;
    for (int k = 0; k < 20; ++k) r.push_back({10.0 + 90.0 * rng.uniform(), -5.0 + rng.uniform()});
    return r;
  }();
  Rows<2> y;
  for (int k = 0; k < 20; ++k) y.push_back({3.0 * rng.uniform(), -40.0 + rng.normal()});
  const auto d = detail::normalise<2, 2>(x, y, FnnTrainingOptions{});
  using Layout = fuzzy::TskLayout<2, 3, 2>;
  std::vector<double> premise(static_cast<std::size_t>(Layout::kConsequentsOffset));
  for (int i = 0; i < 2; ++i) {
    for (int s = 0; s < 3; ++s) {
      premise[static_cast<std::size_t>(Layout::centre_index(i, s))] = rng.uniform();
      premise[static_cast<std::size_t>(Layout::width_index(i, s))] = rng.uniform(0.3, 0.8);
    }
  }
  std::vector<double> consequents(static_cast<std::size_t>(2 * Layout::kConsequentBlock));
  for (double& p : consequents) p = rng.uniform(-1.0, 1.0);
  const auto m = d.model<3>(premise, consequents);
  // The normalised network: the same premise and, per output o, consequent block o.
  for (int o = 0; o < 2; ++o) {
    using Single = fuzzy::TskLayout<2, 3, 1>;
    std::vector<double> params(static_cast<std::size_t>(Single::kParamCount));
    std::copy(premise.begin(), premise.end(), params.begin());
    for (int j = 0; j < Single::kRules; ++j) {
      for (int t = 0; t < Single::kTerms; ++t) {
        params[static_cast<std::size_t>(Single::consequent_index(0, j, t))] =
            consequents[static_cast<std::size_t>((o * Single::kRules + j) * Single::kTerms + t)];
      }
    }
    for (std::size_t k = 0; k < x.size(); ++k) {
      std::array<double, 1> yn{};
      fuzzy::TskEvaluator<double, 2, 3, 1>::forward(params.data(), d.x[k], yn);
      std::array<double, 2> yr{};
      ASSERT_EQ(fuzzy::evaluate(m, x[k], yr, fuzzy::DomainPolicy::kReject), Status::kOk);
      EXPECT_NEAR(
          yr[static_cast<std::size_t>(o)],
          d.scale[static_cast<std::size_t>(o)] * yn[0] + d.mean[static_cast<std::size_t>(o)],
          1e-9 * (1.0 + std::abs(yr[static_cast<std::size_t>(o)])));
    }
  }
}

}  // namespace
}  // namespace cmmcomp::training
