// SPDX-License-Identifier: MIT
/// @file Tests of stage 5 of the trainer (src/training/fnn_interval.hpp): the prediction interval's
/// calibration.
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
#include "training/fnn_interval.hpp"

namespace cmmcomp::training {
namespace {

using namespace fnn_test;

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

// --- The stage on its own ---------------------------------------------------------------------

TEST(FnnCalibrateInterval, ZeroCoverageOrOneDesignPointLeavesTheCalibrationAlone) {
  Rng rng{test::seed() + 31};
  Rows<1> x;
  Rows<1> y;
  for (int k = 0; k < 20; ++k) {
    x.push_back({rng.uniform()});
    y.push_back({rng.normal()});
  }
  FnnTrainingOptions options;
  options.interval_coverage = 0.0;
  const auto d = detail::normalise<1, 1>(x, y, options);
  const detail::RidgeFit<1, 3, 1> fit(d, options);
  TrainingSummary s;
  const detail::RidgeStart start = fit.start(s);
  fuzzy::IntervalCalibration<1> cal;
  detail::calibrate_interval(fit, start.phi, start.u, s.lambda, cal, s);
  EXPECT_FALSE(cal.available());
  EXPECT_EQ(s.interval_samples, 0u);
  EXPECT_TRUE(s.interval_folds.empty());

  options.interval_coverage = 0.9;
  options.interval_folds = IntervalFolds::kRidge;
  detail::calibrate_interval(fit, start.phi, start.u, s.lambda, cal, s);
  EXPECT_TRUE(cal.available());
  EXPECT_EQ(cal.coverage, 0.9);
  EXPECT_EQ(s.interval_samples, 20u);
  EXPECT_EQ(s.interval_folds, std::vector<IntervalFolds>{IntervalFolds::kRidge});
  EXPECT_GT(cal.half_width[0], 0.0);
}

}  // namespace
}  // namespace cmmcomp::training
