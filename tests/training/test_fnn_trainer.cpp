// SPDX-License-Identifier: MIT
/// @file Tests of the Ceres trainer of the T-S network (training/fnn_trainer.hpp).
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

#include "support/test_seed.hpp"

namespace cmmcomp::training {
namespace {

/// Portable generator for test data: the project's one (detail/splitmix64.hpp).
using Rng = detail::SplitMix64;

template <std::size_t N>
using Rows = std::vector<std::array<double, N>>;

/// Raw input ranges used by the synthetic data (PV mm/s, PD mm, AV mm/s, AD mm).
constexpr std::array<std::array<double, 2>, 4> kRanges{{{20, 120}, {10, 300}, {1, 10}, {0.5, 3}}};

/// The paper's Table 3 ranges in the design's units (doe::paper_table3_factors(): SI).
std::array<double, 4> paper_range(bool high) {
  const doe::Design l18 = doe::paper_l18_design();
  std::array<double, 4> out{};
  for (std::size_t i = 0; i < 4; ++i) {
    out[i] = l18.values[0][i];
    for (const auto& run : l18.values)
      out[i] = high ? std::max(out[i], run[i]) : std::min(out[i], run[i]);
  }
  return out;
}

/// A smooth nonlinear function of the four normalised inputs (µm-sized).
double smooth4(const std::array<double, 4>& u) {
  return 8.0 + 6.0 * u[0] - 4.0 * u[1] * u[1] + 3.0 * std::sin(3.0 * u[2]) * u[3] +
         2.0 * u[0] * u[1];
}

/// n random samples of 4 inputs in kRanges; `u` receives the normalised values.
Rows<4> random_inputs4(Rng& rng, std::size_t n, Rows<4>* u) {
  Rows<4> x(n);
  if (u != nullptr) u->resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t i = 0; i < 4; ++i) {
      const double v = rng.uniform();
      x[k][i] = kRanges[i][0] + v * (kRanges[i][1] - kRanges[i][0]);
      if (u != nullptr) (*u)[k][i] = v;
    }
  }
  return x;
}

double rms(const std::vector<double>& e) {
  double s = 0;
  for (double v : e) s += v * v;
  return std::sqrt(s / static_cast<double>(e.size()));
}

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

// --- Ridge initialisation and cross-validation -----------------------------------------------

TEST(FnnTrainer, RidgeInitAloneBeatsConstantPredictor) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 1};
  Rows<4> u_train, u_test;
  const Rows<4> x_train = random_inputs4(rng, 54, &u_train);
  const Rows<4> x_test = random_inputs4(rng, 300, &u_test);
  Rows<1> y_train;
  double mean = 0;
  for (const auto& u : u_train) {
    y_train.push_back({smooth4(u)});
    mean += smooth4(u) / 54.0;
  }
  FnnTrainingOptions options;
  options.max_iterations = 0;  // the ridge initialisation alone (PaperNetwork, 429 parameters)
  const auto result = train_fnn<4, 3, 1>(x_train, y_train, options);
  ASSERT_TRUE(result.summary.usable());
  EXPECT_EQ(result.summary.iterations, 0);
  std::vector<double> e_model, e_const;
  for (std::size_t k = 0; k < x_test.size(); ++k) {
    std::array<double, 1> y{};
    // Random test points may fall just outside the training min/max: extrapolate.
    ASSERT_TRUE(ok(fuzzy::evaluate(result.model, x_test[k], y, fuzzy::DomainPolicy::kExtrapolate)));
    e_model.push_back(y[0] - smooth4(u_test[k]));
    e_const.push_back(mean - smooth4(u_test[k]));
  }
  EXPECT_LT(rms(e_model), 0.35 * rms(e_const)) << rms(e_model) << " vs " << rms(e_const);
  EXPECT_LT(result.summary.cv_rmse[0], 0.5 * rms(e_const));
}

// With 18 samples and 405 consequents the data cannot pin down each rule; the ridge shrinks the
// rules towards the global first-order fit, so a response that is exactly first-order is
// reproduced everywhere, not just at the training points, however strong the ridge. (A ridge
// towards zero would pull the prediction between the samples towards the mean: error ~µm.)
TEST(FnnTrainer, RidgeShrinksTowardsTheGlobalLinearFit) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 7};
  Rows<4> u_train, u_test;
  const Rows<4> x_train = random_inputs4(rng, 18, &u_train);
  const Rows<4> x_test = random_inputs4(rng, 200, &u_test);
  const auto plane = [](const std::array<double, 4>& x) {
    return 3.0 + 0.05 * x[0] - 0.02 * x[1] + 0.7 * x[2] - 1.5 * x[3];
  };
  Rows<1> y_train;
  for (const auto& x : x_train) y_train.push_back({plane(x)});
  for (double lambda : {1e-3, 1.0, 100.0}) {
    FnnTrainingOptions options;
    options.max_iterations = 0;
    options.folds = 3;
    options.lambda = lambda;
    const auto result = train_fnn<4, 3, 1>(x_train, y_train, options);
    ASSERT_TRUE(result.summary.usable());
    double worst = 0;
    for (const auto& x : x_test) {
      std::array<double, 1> y{};
      ASSERT_TRUE(ok(fuzzy::evaluate(result.model, x, y, fuzzy::DomainPolicy::kExtrapolate)));
      worst = std::max(worst, std::abs(y[0] - plane(x)));
    }
    // 1e-6: the tiny ridge that keeps the global fit defined (global_linear_fit) biases it ~1e-8.
    EXPECT_LT(worst, 1e-6) << "lambda " << lambda;
  }
}

TEST(FnnTrainer, CrossValidationChoosesPositiveLambdaWithNoise) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 2};
  Rows<4> u;
  const Rows<4> x = random_inputs4(rng, 54, &u);
  Rows<1> y;
  for (const auto& v : u) y.push_back({smooth4(v) + 1.5 * rng.normal()});
  FnnTrainingOptions options;
  options.max_iterations = 0;
  options.lambda_grid = {0.0, 1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1};
  const auto result = train_fnn<4, 3, 1>(x, y, options);
  ASSERT_TRUE(result.summary.usable());
  ASSERT_EQ(result.summary.cv_mse_grid.size(), options.lambda_grid.size());
  // 429 parameters against 54 noisy samples: the unregularised fit interpolates the noise.
  EXPECT_GE(result.summary.lambda, 1e-4);
  for (double m : result.summary.cv_mse_grid) EXPECT_TRUE(std::isfinite(m));
  EXPECT_GT(result.summary.cv_mse_grid[0], result.summary.cv_mse_grid[4]);
  ASSERT_EQ(result.summary.cv_rmse.size(), 1u);
  EXPECT_TRUE(std::isfinite(result.summary.cv_rmse[0]));
  EXPECT_GT(result.summary.cv_rmse[0], 0.0);
}

TEST(FnnTrainer, SharedPremiseInitMatchesSeparateNetworks) {
  // With the premise at the initialisation, output o of a multi-output network is exactly the
  // single-output network trained on output o.
  Rng rng{test::seed() + 3};
  Rows<2> x;
  Rows<2> y2;
  Rows<1> ya, yb;
  for (int k = 0; k < 30; ++k) {
    const double a = rng.uniform(0, 4), b = rng.uniform(-1, 1);
    x.push_back({a, b});
    y2.push_back({std::sin(a) + b, 100.0 * a * b});
    ya.push_back({y2.back()[0]});
    yb.push_back({y2.back()[1]});
  }
  FnnTrainingOptions options;
  options.max_iterations = 0;
  options.lambda = 1e-3;
  const auto multi = train_fnn<2, 3, 2>(x, y2, options);
  const auto one = train_fnn<2, 3, 1>(x, ya, options);
  const auto two = train_fnn<2, 3, 1>(x, yb, options);
  for (int j = 0; j < 9; ++j) {
    for (int t = 0; t < 3; ++t) {
      EXPECT_NEAR(
          multi.model.params.consequent(0, j, t), one.model.params.consequent(0, j, t), 1e-9);
      EXPECT_NEAR(
          multi.model.params.consequent(1, j, t), two.model.params.consequent(0, j, t), 1e-7);
    }
  }
}

// --- Determinism -----------------------------------------------------------------------------

template <int kI, int kS, int kO>
bool bit_identical(const fuzzy::TskModel<double, kI, kS, kO>& a,
                   const fuzzy::TskModel<double, kI, kS, kO>& b) {
  return std::memcmp(a.params.values.data(), b.params.values.data(), sizeof(a.params.values)) == 0;
}

TEST(FnnTrainer, SameSeedGivesBitIdenticalParameters) {
  Rng rng{test::seed() + 4};
  Rows<2> x;
  Rows<2> y;
  for (int k = 0; k < 40; ++k) {
    const double a = rng.uniform(0, 1), b = rng.uniform(0, 1);
    x.push_back({a, b});
    y.push_back({a * a + 0.1 * rng.normal(), std::cos(3 * b) + 0.1 * rng.normal()});
  }
  FnnTrainingOptions options;
  options.seed = 77;
  options.max_iterations = 5;
  const auto r1 = train_fnn<2, 3, 2>(x, y, options);
  const auto r2 = train_fnn<2, 3, 2>(x, y, options);
  EXPECT_TRUE(bit_identical(r1.model, r2.model));
  EXPECT_EQ(r1.summary.lambda, r2.summary.lambda);
  EXPECT_EQ(r1.summary.cv_mse_grid, r2.summary.cv_mse_grid);
  EXPECT_EQ(r1.summary.final_cost, r2.summary.final_cost);

  options.method = FnnMethod::kGradientDescent;
  options.epochs = 20;
  const auto g1 = train_fnn<2, 3, 2>(x, y, options);
  const auto g2 = train_fnn<2, 3, 2>(x, y, options);
  EXPECT_TRUE(bit_identical(g1.model, g2.model));
  options.seed = 78;  // another seed: another random start
  const auto g3 = train_fnn<2, 3, 2>(x, y, options);
  EXPECT_FALSE(bit_identical(g1.model, g3.model));
}

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

// --- Jacobian of the residual ----------------------------------------------------------------

template <int kI, int kS>
void check_gradient(std::uint64_t seed) {
  using Residual = FnnSampleResidual<kI, kS>;
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
  ceres::DynamicAutoDiffCostFunction<Residual, kFnnJetStride> cost(functor);
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
  FnnSampleResidual<2, 3> r;
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

// --- Errors ----------------------------------------------------------------------------------

Rows<2> line_inputs(int n) {
  Rows<2> x;
  for (int k = 0; k < n; ++k) x.push_back({static_cast<double>(k), static_cast<double>(k * k)});
  return x;
}

std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no ConfigError";
}

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

// --- Prediction-interval calibration (step 7, docs/uncertainty.md) --------------------------

TEST(ConformalQuantile, IsTheCeilNPlusOneTimesCthSmallest) {
  // n = 5 scores, unsorted: the rank is ⌈6c⌉.
  const std::vector<double> s{5.0, 1.0, 4.0, 2.0, 3.0};
  EXPECT_EQ(conformal_quantile(s, 0.1), 1.0);   // ⌈0.6⌉ = 1
  EXPECT_EQ(conformal_quantile(s, 0.25), 2.0);  // ⌈1.5⌉ = 2
  EXPECT_EQ(conformal_quantile(s, 0.5), 3.0);   // ⌈3⌉ = 3: an exact integer is not rounded up
  EXPECT_EQ(conformal_quantile(s, 0.6), 4.0);   // ⌈3.6⌉ = 4
  EXPECT_EQ(conformal_quantile(s, 0.8), 5.0);   // ⌈4.8⌉ = 5 = n
  // A tiny coverage still gives rank 1 (the clamp's lower end), never index −1.
  EXPECT_EQ(conformal_quantile(s, 1e-12), 1.0);

  // c = 0.95 with the scores 1…n (in a scrambled order): rank ⌈0.95(n + 1)⌉.
  const auto scrambled = [](int n) {
    std::vector<double> v;
    for (int k = 0; k < n; ++k) v.push_back(static_cast<double>((k * 7) % n + 1));  // 7 ∤ n
    return v;
  };
  EXPECT_EQ(conformal_quantile(scrambled(39), 0.95), 38.0);   // ⌈38⌉ = 38 < n
  EXPECT_EQ(conformal_quantile(scrambled(40), 0.95), 39.0);   // ⌈38.95⌉ = 39
  EXPECT_EQ(conformal_quantile(scrambled(99), 0.95), 95.0);   // ⌈95⌉ = 95
  EXPECT_EQ(conformal_quantile(scrambled(100), 0.95), 96.0);  // ⌈95.95⌉ = 96
  EXPECT_EQ(conformal_quantile(scrambled(38), 0.95), 38.0);   // ⌈37.05⌉ = 38 = n: the largest
  EXPECT_EQ(conformal_quantile(scrambled(19), 0.95), 19.0);   // ⌈19⌉ = 19 = n: the largest
}

TEST(ConformalQuantile, RankAboveNIsClampedToTheLargest) {
  // (n + 1)c > n ⇔ n < c/(1 − c): for c = 0.95, n < 19. The rank is clamped to n.
  const std::vector<double> s{5.0, 1.0, 4.0, 2.0, 3.0};  // ⌈5.7⌉ = 6 > 5
  EXPECT_EQ(conformal_quantile(s, 0.95), 5.0);
  EXPECT_EQ(conformal_quantile(s, 0.999), 5.0);
  EXPECT_EQ(conformal_quantile({3.5}, 0.95), 3.5);  // ⌈1.9⌉ = 2 > 1
  EXPECT_EQ(conformal_quantile({3.5}, 0.5), 3.5);   // ⌈1⌉ = 1
  std::vector<double> eighteen;
  for (int k = 18; k >= 1; --k) eighteen.push_back(k);  // ⌈18.05⌉ = 19 > 18
  EXPECT_EQ(conformal_quantile(eighteen, 0.95), 18.0);
  EXPECT_EQ(conformal_quantile({}, 0.95), 0.0);  // no scores: 0
}

TEST(ConformalQuantile, TiesCountEachScoreOnce) {
  // Sorted: 1 2 2 2 7 7. Every copy of a tied score takes its own rank.
  const std::vector<double> s{2.0, 7.0, 1.0, 2.0, 7.0, 2.0};
  EXPECT_EQ(conformal_quantile(s, 0.25), 2.0);  // ⌈1.75⌉ = 2
  EXPECT_EQ(conformal_quantile(s, 0.5), 2.0);   // ⌈3.5⌉ = 4: the last of the three 2s
  EXPECT_EQ(conformal_quantile(s, 0.7), 7.0);   // ⌈4.9⌉ = 5: the first 7
  EXPECT_EQ(conformal_quantile(s, 0.1), 1.0);   // ⌈0.7⌉ = 1
  const std::vector<double> zeros(20, 0.0);     // all tied at 0 (e.g. gains all covered)
  EXPECT_EQ(conformal_quantile(zeros, 0.95), 0.0);
}

TEST(ConformalQuantile, MatchesACountingDefinition) {
  // Against an independent formulation: the smallest score s with #{scores ≤ s} ≥ r, where
  // r = min(⌈(n + 1)c⌉, n), on random sizes, coverages and heavily tied scores.
  Rng rng{test::seed() + 41};
  SCOPED_TRACE(test::seed_message());
  for (int trial = 0; trial < 500; ++trial) {
    const std::size_t n = 1 + static_cast<std::size_t>(rng.below(60));
    const double c = rng.uniform(0.01, 0.99);
    std::vector<double> s(n);
    for (double& v : s) v = static_cast<double>(rng.below(8));  // ties
    const double nn = static_cast<double>(n);
    const std::size_t r = std::min(static_cast<std::size_t>(std::ceil((nn + 1.0) * c)), n);
    double expected = std::numeric_limits<double>::infinity();
    for (double cand : s) {
      const auto below = static_cast<std::size_t>(
          std::count_if(s.begin(), s.end(), [cand](double v) { return v <= cand; }));
      if (below >= r) expected = std::min(expected, cand);
    }
    ASSERT_EQ(conformal_quantile(s, c), expected) << "n " << n << ", c " << c;
  }
}

/// 150 design points × 4 repeats on two inputs, targets linear in the inputs plus independent
/// Gaussian noise of σ = `sigma[o]` per output: a first-order model fits the mean exactly, so the
/// out-of-fold residuals are the noise up to a small estimation error. `noise` receives it.
struct LinearGaussianData {
  Rows<2> x;
  Rows<2> y;
  std::array<std::vector<double>, 2> noise;
};

LinearGaussianData linear_gaussian(std::uint64_t seed, std::array<double, 2> sigma) {
  Rng rng{seed};
  LinearGaussianData d;
  for (int p = 0; p < 150; ++p) {
    const std::array<double, 2> x{rng.uniform(20.0, 120.0), rng.uniform(10.0, 300.0)};
    for (int r = 0; r < 4; ++r) {
      const std::array<double, 2> e{sigma[0] * rng.normal(), sigma[1] * rng.normal()};
      d.x.push_back(x);
      d.y.push_back({5.0 + 0.03 * x[0] - 0.01 * x[1] + e[0], -10.0 + 0.08 * x[1] + e[1]});
      d.noise[0].push_back(std::abs(e[0]));
      d.noise[1].push_back(std::abs(e[1]));
    }
  }
  return d;
}

TEST(FnnTrainerInterval, HalfWidthIsTheGaussianQuantileOfTheNoise) {
  SCOPED_TRACE(test::seed_message());
  // Output 1 in a unit 8× larger than output 0: h must come out in each output's raw unit.
  const std::array<double, 2> sigma{0.5, 4.0};
  const LinearGaussianData d = linear_gaussian(test::seed() + 43, sigma);
  const std::size_t n = d.x.size();  // 600 scores per output
  // |N(0, σ²)| quantiles: Φ⁻¹((1 + c)/2)·σ.
  const std::array<std::pair<double, double>, 2> cases{{{0.95, 1.959964}, {0.5, 0.674490}}};
  std::array<std::array<double, 2>, 2> h{};
  for (std::size_t k = 0; k < cases.size(); ++k) {
    const double c = cases[k].first;
    FnnTrainingOptions options;
    options.max_iterations = 0;  // the calibration does not use LM (ridge fits only)
    options.interval_coverage = c;
    const auto result = train_fnn<2, 3, 2>(d.x, d.y, options);
    ASSERT_TRUE(result.summary.usable());
    ASSERT_TRUE(result.interval.available());
    EXPECT_EQ(result.interval.coverage, c);
    EXPECT_EQ(result.summary.interval_samples, n);
    for (std::size_t o = 0; o < 2; ++o) {
      h[k][o] = result.interval.half_width[o];
      const double z = h[k][o] / sigma[o];
      // Sampling error of the quantile of 600 scores, 1 SE: ~4 % of it for c = 0.95, ~5 % for
      // c = 0.5. The tolerances (3.75 and 3.6 SE) still exclude 1.645 σ and 2.576 σ (90 % and
      // 99 %) for c = 0.95, and 0.5 σ and σ for c = 0.5.
      const double tol = c > 0.9 ? 0.15 : 0.18;
      EXPECT_NEAR(z, cases[k].second, tol * cases[k].second) << "c " << c << ", output " << o;
      // Free of the noise's own sampling error: the same rule applied to the true |noise| of
      // these samples. The scores differ from it only by the fits' estimation error, which
      // shows most in the tail: over CMMCOMP_TEST_SEED = 1…40 the difference was at most
      // 0.21 σ at c = 0.95 (3 of 40 seeds above 0.1 σ) and 0.075 σ at c = 0.5.
      const double oracle = conformal_quantile(d.noise[o], c);
      EXPECT_NEAR(h[k][o], oracle, (c > 0.9 ? 0.25 : 0.1) * sigma[o])
          << "c " << c << ", output " << o;
      EXPECT_GE(result.interval.extrapolation_gain[o], 0.0);
      EXPECT_TRUE(std::isfinite(result.interval.extrapolation_gain[o]));
    }
  }
  for (std::size_t o = 0; o < 2; ++o) {
    EXPECT_GT(h[0][o], h[1][o]) << "output " << o;
    // 1.96/0.674 = 2.91.
    EXPECT_NEAR(h[0][o] / h[1][o], 1.959964 / 0.674490, 0.6) << "output " << o;
  }
  // Per raw unit: the two outputs' half-widths scale with their σ (ratio 8).
  EXPECT_NEAR(h[0][1] / h[0][0], sigma[1] / sigma[0], 0.2 * sigma[1] / sigma[0]);
}

/// Noise that grows towards the corners of the box: σ·(1 + 3κ(x)), κ the corner share
/// (fuzzy::corner_share) of x in the box [20, 120] × [10, 300].
double corner_noise_scale(const std::array<double, 2>& x) {
  const std::array<fuzzy::InputRange, 2> box{{{20.0, 120.0}, {10.0, 300.0}}};
  return 1.0 + 3.0 * fuzzy::corner_share(box, x);
}

// docs/uncertainty.md, step 4: residuals that grow towards the corners give a corner gain near
// their growth, and the interval then covers the corners; noise that does not grow gives about
// none.
TEST(FnnTrainerInterval, CornerGainFollowsResidualsThatGrowTowardsTheCorners) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 77};
  Rows<2> x, y_growing, y_flat;
  for (int p = 0; p < 300; ++p) {
    // Half the design points near the corners, so that the growth is seen.
    const bool corner = p % 2 == 0;
    const std::array<double, 2> at{
        corner ? (rng.uniform(0.0, 1.0) < 0.5 ? rng.uniform(20.0, 25.0) : rng.uniform(115.0, 120.0))
               : rng.uniform(20.0, 120.0),
        corner ? (rng.uniform(0.0, 1.0) < 0.5 ? rng.uniform(10.0, 25.0) : rng.uniform(285.0, 300.0))
               : rng.uniform(10.0, 300.0)};
    for (int r = 0; r < 2; ++r) {
      const double mean = 5.0 + 0.03 * at[0] - 0.01 * at[1];
      const double e = 0.5 * rng.normal();
      x.push_back(at);
      y_growing.push_back({mean + e * corner_noise_scale(at), mean + e});
      y_flat.push_back({mean + e, mean + e});
    }
  }
  FnnTrainingOptions options;
  options.max_iterations = 0;
  const auto growing = train_fnn<2, 3, 2>(x, y_growing, options);
  ASSERT_TRUE(growing.interval.available());
  // The residuals grow by 1 + 3κ: the fitted gain is about 3 (it is fitted on |r|, whose mean
  // grows by the same factor).
  EXPECT_GT(growing.interval.corner_gain[0], 1.5);
  EXPECT_LT(growing.interval.corner_gain[0], 6.0);
  EXPECT_LT(growing.interval.corner_gain[1], 0.75);  // output 1's noise does not grow
  const auto flat = train_fnn<2, 3, 2>(x, y_flat, options);
  EXPECT_LT(flat.interval.corner_gain[0], 0.75);

  // Fresh moves at the corners: the calibrated interval covers about 95 % of them, where one
  // without the corner term (h alone) would cover far fewer.
  int covered = 0, covered_flat_width = 0;
  const int n = 2000;
  for (int k = 0; k < n; ++k) {
    const std::array<double, 2> at{rng.uniform(0.0, 1.0) < 0.5 ? 20.0 : 120.0,
                                   rng.uniform(0.0, 1.0) < 0.5 ? 10.0 : 300.0};
    const double e = 0.5 * rng.normal() * corner_noise_scale(at);  // κ = 1: 4 σ
    std::array<double, 2> u{};
    fuzzy::interval_half_widths_at(growing.interval, growing.model.ranges, at, u);
    covered += std::abs(e) <= u[0] ? 1 : 0;
    covered_flat_width += std::abs(e) <= growing.interval.half_width[0] ? 1 : 0;
  }
  EXPECT_GT(covered, 0.90 * n);
  EXPECT_LT(covered_flat_width, 0.75 * n);
}

TEST(FnnTrainerInterval, ExtrapolationGainIsFiniteNonNegativeAndPositiveUnderCurvature) {
  SCOPED_TRACE(test::seed_message());
  // One input, the same samples and noise, two targets: y = 40 u + e, which a fit to two thirds
  // of the range extrapolates correctly, and y = 40 u² + e, whose curvature in the held-out
  // third such a fit misses, so the interval has to grow outside the box (gain > 0).
  Rng rng{test::seed() + 47};
  Rows<1> x;
  Rows<1> line;
  Rows<1> curve;
  for (int k = 0; k < 120; ++k) {
    const double u = rng.uniform();
    const double e = 0.2 * rng.normal();
    x.push_back({10.0 + 90.0 * u});
    line.push_back({40.0 * u + e});
    curve.push_back({40.0 * u * u + e});
  }
  FnnTrainingOptions options;
  options.max_iterations = 0;
  const auto straight = train_fnn<1, 3, 1>(x, line, options);
  const auto curved = train_fnn<1, 3, 1>(x, curve, options);
  for (const auto* r : {&straight, &curved}) {
    ASSERT_TRUE(r->interval.available());
    EXPECT_TRUE(std::isfinite(r->interval.half_width[0]));
    EXPECT_GT(r->interval.half_width[0], 0.0);
    EXPECT_TRUE(std::isfinite(r->interval.extrapolation_gain[0]));
    EXPECT_GE(r->interval.extrapolation_gain[0], 0.0);
  }
  // Over 40 seeds (CMMCOMP_TEST_SEED=1…40) the curve's gain was 1.4 to 32. The line's is not
  // reliably ~0 (0 to 4.3; 0.46 at the default seed): a held-out sample just outside the rest's
  // box (d → 0) whose noise exceeds h needs (|e|/h − 1)/d, unbounded. So no ordering of the two
  // is asserted, only that curvature gives a clearly positive gain.
  EXPECT_GT(curved.interval.extrapolation_gain[0], 0.5);
}

// --- Which fold models (docs/uncertainty.md, "Which fold models") ----------------------------

/// One input, two outputs on 80 design points × 3 repeats with Gaussian noise σ 0.2: output 0 a
/// narrow bump at u = 0.25 that the ridge fit at the initial premise (centres 0, 0.5, 1, widths
/// 0.5) smooths over and 30 LM iterations resolve by moving and narrowing a set (training RMSE
/// 0.49 → 0.21 at the default seed); output 1 a line, which the ridge fit already has.
struct BumpData {
  Rows<1> x;
  Rows<2> y;
};

double bump_mean(double u) { return 3.0 * std::exp(-std::pow((u - 0.25) / 0.1, 2)); }

BumpData bump_data(std::uint64_t seed) {
  Rng rng{seed};
  BumpData d;
  for (int p = 0; p < 80; ++p) {
    // Evenly spaced design points, so that only the noise depends on the seed (with random
    // points LM missed the bump on a few seeds).
    const double u = (p + 0.5) / 80.0;
    for (int r = 0; r < 3; ++r) {
      d.x.push_back({10.0 + 90.0 * u});
      d.y.push_back({bump_mean(u) + 0.2 * rng.normal(), 2.0 * u + 0.2 * rng.normal()});
    }
  }
  return d;
}

/// The calibration's mean half-width over the training inputs (all inside the box, d = 0):
/// h·(1 + k·mean κ), the quantity kNarrower compares.
template <int kOutputs>
double mean_half_width(const fuzzy::IntervalCalibration<kOutputs>& cal,
                       const std::array<fuzzy::InputRange, 1>& ranges,
                       const Rows<1>& x,
                       std::size_t o) {
  double sum = 0.0;
  for (const auto& at : x) {
    std::array<double, kOutputs> u{};
    fuzzy::interval_half_widths_at(cal, ranges, at, u);
    sum += u[o];
  }
  return sum / static_cast<double>(x.size());
}

/// The same training with the ridge folds, the folds as served and the narrower of the two.
struct EachFoldKind {
  FnnTrainingResult<1, 3, 2> ridge, served, narrower;
};
EachFoldKind train_with_each_fold_kind(const BumpData& d, FnnTrainingOptions options) {
  EachFoldKind t;
  options.interval_folds = IntervalFolds::kRidge;
  t.ridge = train_fnn<1, 3, 2>(d.x, d.y, options);
  options.interval_folds = IntervalFolds::kAsServed;
  t.served = train_fnn<1, 3, 2>(d.x, d.y, options);
  options.interval_folds = IntervalFolds::kNarrower;
  t.narrower = train_fnn<1, 3, 2>(d.x, d.y, options);
  return t;
}

/// Of n fresh moves of bump_data's process (random stream `seed`), how many lie within the
/// `model`'s prediction ± U of `served` and of `ridge`, per output. Only the first `outputs`
/// outputs are drawn and counted (the draws, and so the moves, depend on it).
struct FreshCoverage {
  std::array<int, 2> served{}, ridge{};
};
FreshCoverage coverage_on_fresh_moves(const fuzzy::TskModel<double, 1, 3, 2>& model,
                                      const fuzzy::IntervalCalibration<2>& served,
                                      const fuzzy::IntervalCalibration<2>& ridge,
                                      std::uint64_t seed,
                                      int n,
                                      std::size_t outputs) {
  Rng rng{seed};
  FreshCoverage c;
  for (int k = 0; k < n; ++k) {
    const double u = rng.uniform();
    const std::array<double, 1> at{10.0 + 90.0 * u};
    std::array<double, 2> y{bump_mean(u) + 0.2 * rng.normal(), 0.0};
    if (outputs > 1) y[1] = 2.0 * u + 0.2 * rng.normal();
    std::array<double, 2> predicted{};
    EXPECT_TRUE(ok(fuzzy::evaluate(model, at, predicted, fuzzy::DomainPolicy::kClamp)));
    std::array<double, 2> u_served{}, u_ridge{};
    fuzzy::interval_half_widths_at(served, model.ranges, at, u_served);
    fuzzy::interval_half_widths_at(ridge, model.ranges, at, u_ridge);
    for (std::size_t o = 0; o < outputs; ++o) {
      c.served[o] += std::abs(y[o] - predicted[o]) <= u_served[o] ? 1 : 0;
      c.ridge[o] += std::abs(y[o] - predicted[o]) <= u_ridge[o] ? 1 : 0;
    }
  }
  return c;
}

TEST(FnnTrainerInterval, AsServedFoldsFollowTheServedModelWhereLmImprovesOnTheRidgeFit) {
  SCOPED_TRACE(test::seed_message());
  const BumpData d = bump_data(test::seed() + 61);
  FnnTrainingOptions options;
  options.max_iterations = 30;
  const auto [ridge, served, narrower] = train_with_each_fold_kind(d, options);
  ASSERT_TRUE(ridge.summary.usable());
  // The calibration never changes the served model.
  EXPECT_EQ(ridge.model.params.values, served.model.params.values);
  EXPECT_EQ(ridge.model.params.values, narrower.model.params.values);
  EXPECT_EQ(ridge.summary.interval_folds,
            (std::vector<IntervalFolds>{IntervalFolds::kRidge, IntervalFolds::kRidge}));
  EXPECT_EQ(served.summary.interval_folds,
            (std::vector<IntervalFolds>{IntervalFolds::kAsServed, IntervalFolds::kAsServed}));
  // LM resolves the bump: the served model is far better than its ridge start on output 0.
  ASSERT_LT(ridge.summary.train_rmse[0], 0.6 * ridge.summary.init_train_rmse[0]);
  // So the ridge folds' interval is much wider than the as-served one there,
  EXPECT_LT(served.interval.half_width[0], 0.75 * ridge.interval.half_width[0]);
  // and fresh moves show which is right: the as-served interval covers about its 95 %, the
  // ridge one nearly everything.
  const int n = 4000;
  const FreshCoverage covered = coverage_on_fresh_moves(
      served.model, served.interval, ridge.interval, test::seed() + 62, n, 1);
  EXPECT_GT(covered.served[0], 0.90 * n);
  EXPECT_LT(covered.served[0], 0.99 * n);
  EXPECT_GT(covered.ridge[0], covered.served[0]);

  // kNarrower takes, per output, the whole calibration (h and k) of the narrower source.
  for (std::size_t o = 0; o < 2; ++o) {
    const double w_ridge = mean_half_width(ridge.interval, ridge.model.ranges, d.x, o);
    const double w_served = mean_half_width(served.interval, served.model.ranges, d.x, o);
    const bool take_served = w_served < w_ridge;
    const auto& chosen = take_served ? served.interval : ridge.interval;
    EXPECT_EQ(narrower.summary.interval_folds[o],
              take_served ? IntervalFolds::kAsServed : IntervalFolds::kRidge)
        << "output " << o;
    EXPECT_EQ(narrower.interval.half_width[o], chosen.half_width[o]) << "output " << o;
    EXPECT_EQ(narrower.interval.corner_gain[o], chosen.corner_gain[o]) << "output " << o;
    EXPECT_LE(mean_half_width(narrower.interval, narrower.model.ranges, d.x, o),
              std::min(w_ridge, w_served))
        << "output " << o;
  }
  EXPECT_EQ(narrower.summary.interval_folds[0], IntervalFolds::kAsServed);
  EXPECT_EQ(interval_method(narrower.summary.interval_folds, {"bump", "line"}),
            "split-conformal on design-point-grouped CV residuals (bump as-served, line " +
                std::string(to_string(narrower.summary.interval_folds[1])) +
                "); extrapolation gain from held-out ends");
}

TEST(FnnTrainerInterval, WithoutLmTheFoldModelsAreTheRidgeFits) {
  SCOPED_TRACE(test::seed_message());
  // max_iterations = 0 serves the ridge initialisation, so the ridge folds are the folds as
  // served: every choice gives the same calibration, from the ridge folds.
  const BumpData d = bump_data(test::seed() + 63);
  FnnTrainingOptions options;
  options.max_iterations = 0;
  std::vector<fuzzy::IntervalCalibration<2>> calibrations;
  for (const IntervalFolds f :
       {IntervalFolds::kRidge, IntervalFolds::kAsServed, IntervalFolds::kNarrower}) {
    options.interval_folds = f;
    const auto r = train_fnn<1, 3, 2>(d.x, d.y, options);
    EXPECT_EQ(r.summary.interval_folds,
              (std::vector<IntervalFolds>{IntervalFolds::kRidge, IntervalFolds::kRidge}))
        << to_string(f);
    calibrations.push_back(r.interval);
  }
  EXPECT_EQ(calibrations[0], calibrations[1]);
  EXPECT_EQ(calibrations[0], calibrations[2]);
}

TEST(FnnTrainerInterval, GradientDescentIsCalibratedOnItsOwnFoldModels) {
  SCOPED_TRACE(test::seed_message());
  // GD starts from a random model, not from the ridge fit, and a short run leaves it far from
  // any ridge fit: the ridge folds would calibrate another model's error. By default (and with
  // kAsServed) GD's folds are GD runs; kRidge still gives the ridge folds, on request.
  const BumpData d = bump_data(test::seed() + 64);
  FnnTrainingOptions options;
  options.method = FnnMethod::kGradientDescent;
  options.epochs = 200;
  options.goal = 0.0;
  const auto [ridge, served, by_default] = train_with_each_fold_kind(d, options);
  ASSERT_TRUE(ridge.summary.usable()) << ridge.summary.message;
  EXPECT_EQ(ridge.model.params.values, served.model.params.values);
  EXPECT_EQ(ridge.model.params.values, by_default.model.params.values);
  const std::vector<IntervalFolds> as_served{IntervalFolds::kAsServed, IntervalFolds::kAsServed};
  EXPECT_EQ(served.summary.interval_folds, as_served);
  EXPECT_EQ(by_default.summary.interval_folds, as_served);
  EXPECT_EQ(by_default.interval, served.interval);
  EXPECT_EQ(ridge.summary.interval_folds,
            (std::vector<IntervalFolds>{IntervalFolds::kRidge, IntervalFolds::kRidge}));
  // Fresh moves: the GD folds' interval covers about its 95 % on both outputs; the ridge
  // folds' one, calibrated on far better fits, covers much less of the GD model's error.
  // Measured: GD folds covered 88.5-99.9 % (seeds 1-40), ridge folds 75.4-88.6 % (seeds 1-20).
  const int n = 4000;
  const FreshCoverage covered = coverage_on_fresh_moves(
      served.model, served.interval, ridge.interval, test::seed() + 65, n, 2);
  for (std::size_t o = 0; o < 2; ++o) {
    EXPECT_GT(covered.served[o], 0.85 * n) << "output " << o;
    EXPECT_LT(covered.served[o], 0.999 * n) << "output " << o;
  }
  EXPECT_LT(covered.ridge[0], 0.90 * n);
  EXPECT_GT(covered.served[0], covered.ridge[0] + 0.04 * n);
}

TEST(FnnTrainerInterval, RejectsAnIntervalFoldsValueOutsideTheEnum) {
  FnnTrainingOptions o;
  o.interval_folds = static_cast<IntervalFolds>(7);
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_EQ(why, "interval_folds is not an IntervalFolds value");
  EXPECT_STREQ(to_string(IntervalFolds::kRidge), "ridge");
  EXPECT_STREQ(to_string(IntervalFolds::kAsServed), "as-served");
  EXPECT_STREQ(to_string(IntervalFolds::kNarrower), "narrower");
}

TEST(FnnTrainerInterval, ZeroCoverageMeansNoCalibration) {
  SCOPED_TRACE(test::seed_message());
  const LinearGaussianData d = linear_gaussian(test::seed() + 53, {0.5, 4.0});
  FnnTrainingOptions options;
  options.max_iterations = 0;
  options.interval_coverage = 0.0;
  const auto none = train_fnn<2, 3, 2>(d.x, d.y, options);
  ASSERT_TRUE(none.summary.usable());
  EXPECT_FALSE(none.interval.available());
  EXPECT_EQ(none.interval.coverage, 0.0);
  EXPECT_EQ(none.interval, (fuzzy::IntervalCalibration<2>{}));  // every half-width and gain 0
  EXPECT_EQ(none.summary.interval_samples, 0u);
  // The same data with a coverage is calibrated: it is the 0 that turns calibration off.
  options.interval_coverage = 0.95;
  const auto some = train_fnn<2, 3, 2>(d.x, d.y, options);
  EXPECT_TRUE(some.interval.available());
  EXPECT_EQ(some.summary.interval_samples, d.x.size());
  // And the model itself does not depend on the calibration.
  EXPECT_EQ(some.model.params.values, none.model.params.values);
}

TEST(FnnTrainerInterval, RejectsCoverageOutsideZeroOrOpenUnitInterval) {
  const std::string expected = "interval_coverage must be 0 (no interval) or in (0, 1)";
  for (double c : {1.0,
                   1.5,
                   -0.05,
                   -1e-300,
                   std::numeric_limits<double>::quiet_NaN(),
                   std::numeric_limits<double>::infinity()}) {
    FnnTrainingOptions o;
    o.interval_coverage = c;
    std::string why;
    EXPECT_FALSE(o.is_valid(&why)) << c;
    EXPECT_EQ(why, expected) << c;
    const Rows<2> x = line_inputs(10);
    const Rows<1> y(10, {1.0});
    EXPECT_NE(
        message_of([&] { train_fnn<2, 3, 1>(x, y, o); }).find("FNN training options: " + expected),
        std::string::npos)
        << c;
  }
  for (double c : {0.0, 1e-9, 0.5, 0.95, 0.999}) {
    FnnTrainingOptions o;
    o.interval_coverage = c;
    EXPECT_TRUE(o.is_valid(nullptr)) << c;
  }
}

// --- Dataset rows and the paper's sizes ------------------------------------------------------

TEST(FnnTrainer, SamplesFromDatasetRowsFollowTheInputSet) {
  DatasetRow r;
  r.pv_mm_s = 1;
  r.pd_mm = 2;
  r.av_mm_s = 3;
  r.ad_mm = 4;
  r.mpe_um = 5;
  r.rpe_um = -6;
  r.mae_um = 7;
  r.rae_um = -8;
  r.y_mm = 9;
  const Samples<4> s = samples<PaperInputs>({r, r});
  ASSERT_EQ(s.inputs.size(), 2u);
  EXPECT_EQ(s.inputs[1], (std::array<double, 4>{1, 2, 3, 4}));
  EXPECT_EQ(s.targets[0], (std::array<double, 4>{5, -6, 7, -8}));
  const Samples<5> y = samples<CarriageInputs>({r});
  EXPECT_EQ(y.inputs[0], (std::array<double, 5>{1, 2, 3, 4, 9}));
  const Samples<2> other = samples<InputSet<Feature::kY, Feature::kAv>>({r});
  EXPECT_EQ(other.inputs[0], (std::array<double, 2>{9, 3}));
  EXPECT_EQ(input_labels<CarriageInputs>(),
            (std::vector<std::string>{"PV", "PD", "AV", "AD", "Y"}));
  EXPECT_STREQ(to_string(FnnMethod::kGradientDescent), "gradient-descent");
}

// --- The prior on a designed experiment (fnn_prior.hpp, docs/training.md "The prior") ----------

/// The paper's L18 × `repeats` in raw units (PV, PD, AV, AD at their Table 3 levels).
Rows<4> paper_l18_inputs(int repeats) {
  const doe::Design l18 = doe::replicate(doe::paper_l18_design(), repeats);
  Rows<4> x;
  for (const auto& run : l18.values) x.push_back({run[0], run[1], run[2], run[3]});
  return x;
}

/// A response of PV and PD only that bends along a diagonal of their square, like the twin's RPE
/// along the triangular boundary (u: inputs normalised over the Table 3 ranges).
double bent2(const std::array<double, 4>& u) {
  return 6.0 + 4.0 * u[0] + 6.0 / (1.0 + 4.0 * (u[1] - u[0] + 1.0));
}

std::array<double, 4> normalised_on(const Rows<4>& x, const std::array<double, 4>& v) {
  std::array<double, 4> u{};
  for (std::size_t i = 0; i < 4; ++i) {
    double lo = x[0][i], hi = lo;
    for (const auto& r : x) {
      lo = std::min(lo, r[i]);
      hi = std::max(hi, r[i]);
    }
    u[i] = (v[i] - lo) / (hi - lo);
  }
  return u;
}

TEST(FnnTrainer, OnTheL18TheNetworkFollowsTheCellMeansBetweenTheLevels) {
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 31};
  const Rows<4> x = paper_l18_inputs(3);
  Rows<1> y;
  for (const auto& v : x) y.push_back({bent2(normalised_on(x, v)) + 0.05 * rng.normal()});
  FnnTrainingOptions options;
  options.input_names = {"PV", "PD", "AV", "AD"};
  options.interval_coverage = 0;
  const auto result = train_fnn<4, 3, 1>(x, y, options);
  ASSERT_TRUE(result.summary.usable());
  ASSERT_EQ(result.summary.prior.size(), 1u);
  EXPECT_EQ(result.summary.prior[0].rfind("quadratic(PV×PD)", 0), 0u) << result.summary.prior[0];
  EXPECT_EQ(result.summary.design_points, 18u);
  // 18 design points cannot place 24 premise parameters: LM does not run.
  EXPECT_EQ(result.summary.iterations, 0);
  EXPECT_NE(result.summary.message.find("18 design points"), std::string::npos);
  // Between the levels the network follows the quadratic through the nine (PV, PD) cell means,
  // the most three levels can tell (rms 0.21 against the cells' 0.21 when written; with the
  // first-order prior of other data, 0.47, which fails here).
  std::vector<double> net, cells, plane;
  const double lv[3] = {0.0, 0.5, 1.0};
  auto lagrange = [&lv](double t, int i) {
    double w = 1;
    for (int j = 0; j < 3; ++j) {
      if (j != i) w *= (t - lv[j]) / (lv[i] - lv[j]);
    }
    return w;
  };
  const std::array<double, 4> lo = paper_range(false), hi = paper_range(true);
  for (int k = 0; k < 200; ++k) {
    std::array<double, 4> u{rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()};
    std::array<double, 4> v{};
    for (std::size_t i = 0; i < 4; ++i) v[i] = lo[i] + u[i] * (hi[i] - lo[i]);
    std::array<double, 1> out{};
    ASSERT_TRUE(ok(fuzzy::evaluate(result.model, v, out, fuzzy::DomainPolicy::kExtrapolate)));
    net.push_back(out[0] - bent2(u));
    double interp = 0;
    for (int a = 0; a < 3; ++a) {
      for (int b = 0; b < 3; ++b) {
        interp += lagrange(u[0], a) * lagrange(u[1], b) * bent2({lv[a], lv[b], 0, 0});
      }
    }
    cells.push_back(interp - bent2(u));
  }
  EXPECT_LT(rms(net), 1.5 * rms(cells) + 0.05)
      << "network " << rms(net) << ", cells " << rms(cells);
}

TEST(FnnTrainer, OnTheL18TheIntervalHoldsOutOneDesignPointAtATime) {
  // A response of PV and AV that the prior's quadratic over them holds exactly, with noise σ:
  // the served model is right up to the noise, so a calibrated 95 % interval is about 2σ wide.
  // Five folds of the 18 design points often take both runs of a (PV, AV) cell; each such
  // fold predicts a cell the served model never has to, and the interval came out 1.11 wide
  // (11σ) when this was written. Leaving out one design point at a time keeps every cell:
  // 0.18.
  SCOPED_TRACE(test::seed_message());
  Rng rng{test::seed() + 41};
  constexpr double kSigma = 0.05;
  const Rows<4> x = paper_l18_inputs(3);
  auto response = [](const std::array<double, 4>& u) {
    return 4.0 * u[0] * u[2] + 2.0 * u[0] * u[0];
  };
  Rows<1> y;
  for (const auto& v : x) y.push_back({response(normalised_on(x, v)) + kSigma * rng.normal()});
  FnnTrainingOptions options;
  options.input_names = {"PV", "PD", "AV", "AD"};
  options.interval_folds = IntervalFolds::kRidge;
  const auto result = train_fnn<4, 3, 1>(x, y, options);
  ASSERT_TRUE(result.summary.usable());
  EXPECT_EQ(result.summary.prior[0], "quadratic(PV×AV)");
  ASSERT_TRUE(result.interval.available());
  const double h = result.interval.half_width[0];
  EXPECT_LT(h, 8.0 * kSigma);
  EXPECT_GT(h, 1.0 * kSigma);
  // And it covers held-out moves between the levels.
  const std::array<double, 4> lo = paper_range(false), hi = paper_range(true);
  int covered = 0;
  constexpr int kMoves = 400;
  for (int k = 0; k < kMoves; ++k) {
    std::array<double, 4> u{rng.uniform(), rng.uniform(), rng.uniform(), rng.uniform()};
    std::array<double, 4> v{};
    for (std::size_t i = 0; i < 4; ++i) v[i] = lo[i] + u[i] * (hi[i] - lo[i]);
    std::array<double, 1> out{};
    ASSERT_TRUE(ok(fuzzy::evaluate(result.model, v, out, fuzzy::DomainPolicy::kExtrapolate)));
    covered += std::abs(out[0] - response(u) - kSigma * rng.normal()) <= h ? 1 : 0;
  }
  EXPECT_GE(covered, kMoves * 90 / 100) << "half-width " << h;
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

// Training time is measured by bench/bench_training.cpp (Google Benchmark), not here.

}  // namespace
}  // namespace cmmcomp::training
