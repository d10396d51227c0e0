// SPDX-License-Identifier: MIT
// The prior the trainer's ridge shrinks towards (src/training/fnn_prior.hpp): its shapes, their
// fit and slopes, and the choice of a shape on a designed experiment.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cstddef>
#include <vector>

#include "support/test_seed.hpp"
#include "training/fnn_prior.hpp"

namespace cmmcomp::training::detail {
namespace {

/// The paper's L18 (PV, PD, AV, AD on c2..c5) repeated `repeats` times, inputs normalised to
/// the levels 0, ½, 1; `group` receives each sample's design point.
Eigen::MatrixXd l18_inputs(int repeats, std::vector<std::size_t>* group) {
  const doe::Design l18 = doe::paper_l18_design();
  Eigen::MatrixXd x(l18.runs() * repeats, 4);
  group->clear();
  for (int r = 0; r < repeats; ++r) {
    for (int run = 0; run < l18.runs(); ++run) {
      for (int i = 0; i < 4; ++i) {
        x(r * l18.runs() + run, i) =
            0.5 * l18.level_indices[static_cast<std::size_t>(run)][static_cast<std::size_t>(i)];
      }
      group->push_back(static_cast<std::size_t>(run));
    }
  }
  return x;
}

/// A response of the first two inputs only, bent like the twin's RPE along a diagonal.
double bent(double u0, double u1) { return 6.0 + 4.0 * u0 + 6.0 / (1.0 + 4.0 * (u1 - u0 + 1.0)); }

TEST(FnnPrior, CandidatesStartWithTheGlobalFirstOrderFitAndCoverEveryInputAndPair) {
  const auto c = prior_candidates(4);
  // First-order; 4 single inputs and 6 pairs, each alone and with the other inputs first-order.
  ASSERT_EQ(c.size(), 1u + 2u * 4u + 2u * 6u);
  EXPECT_TRUE(c[0].first_order());
  EXPECT_EQ(c[0].linear, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(c[0].terms(), 5);
  const PriorShape pair_alone{{0, 1}, {}};
  EXPECT_EQ(pair_alone.terms(), 9);
  EXPECT_EQ(pair_alone.describe({"PV", "PD", "AV", "AD"}), "quadratic(PV×PD)");
  const PriorShape with_rest{{2}, {0, 1, 3}};
  EXPECT_EQ(with_rest.terms(), 6);
  EXPECT_EQ(with_rest.describe({"PV", "PD", "AV", "AD"}), "quadratic(AV)+first-order(PV, PD, AD)");
  EXPECT_EQ(c[0].describe({}), "first-order");
}

TEST(FnnPrior, TheQuadraticOfAPairInterpolatesItsNineCellMeans) {
  std::vector<std::size_t> group;
  const Eigen::MatrixXd x = l18_inputs(3, &group);
  cmmcomp::detail::SplitMix64 rng{test::seed() + 1};
  Eigen::VectorXd z(x.rows());
  for (Eigen::Index k = 0; k < x.rows(); ++k) z(k) = bent(x(k, 0), x(k, 1)) + rng.normal();
  std::vector<Eigen::Index> all(static_cast<std::size_t>(x.rows()));
  for (Eigen::Index k = 0; k < x.rows(); ++k) all[static_cast<std::size_t>(k)] = k;
  const PriorShape shape{{0, 1}, {}};
  const Eigen::VectorXd b = fit_prior(shape, x, z, all);
  // Each (PV, PD) cell of the L18 holds two runs, six samples: the fit is their mean.
  for (int a = 0; a < 3; ++a) {
    for (int c = 0; c < 3; ++c) {
      double sum = 0;
      int n = 0;
      for (Eigen::Index k = 0; k < x.rows(); ++k) {
        if (x(k, 0) == 0.5 * a && x(k, 1) == 0.5 * c) {
          sum += z(k);
          ++n;
        }
      }
      ASSERT_EQ(n, 6);
      const double cell[4] = {0.5 * a, 0.5 * c, 0.3, 0.9};  // the other inputs do not enter
      // 1e-4: the fit's tiny ridge (1e-9 of the largest Gram diagonal) on the small d⁴ terms.
      EXPECT_NEAR(prior_features(shape, cell).dot(b), sum / n, 1e-4) << a << ", " << c;
    }
  }
}

TEST(FnnPrior, SlopesAreTheDerivativesOfTheFeatures) {
  cmmcomp::detail::SplitMix64 rng{test::seed() + 2};
  for (const PriorShape& shape : prior_candidates(4)) {
    for (int trial = 0; trial < 5; ++trial) {
      double x[4];
      for (double& v : x) v = rng.uniform();
      for (int i = 0; i < 4; ++i) {
        double hi[4], lo[4];
        for (int j = 0; j < 4; ++j) hi[j] = lo[j] = x[j];
        hi[i] += 1e-6;
        lo[i] -= 1e-6;
        const Eigen::VectorXd numeric =
            (prior_features(shape, hi) - prior_features(shape, lo)) / 2e-6;
        EXPECT_LT((prior_feature_slopes(shape, x, i) - numeric).cwiseAbs().maxCoeff(), 1e-8)
            << shape.describe({}) << " input " << i;
      }
    }
  }
}

TEST(FnnPrior, OnTheL18ItChoosesThePairThatDrivesTheResponse) {
  std::vector<std::size_t> group;
  const Eigen::MatrixXd x = l18_inputs(3, &group);
  cmmcomp::detail::SplitMix64 rng{test::seed() + 3};
  Eigen::VectorXd z(x.rows());
  for (Eigen::Index k = 0; k < x.rows(); ++k) {
    z(k) = bent(x(k, 0), x(k, 1)) + 0.1 * rng.normal();
  }
  const PriorShape chosen = choose_prior_shape(x, z, group, 18);
  EXPECT_EQ(chosen.quadratic, (std::vector<int>{0, 1})) << chosen.describe({});
}

TEST(FnnPrior, AFirstOrderResponseKeepsTheFirstOrderFit) {
  std::vector<std::size_t> group;
  const Eigen::MatrixXd x = l18_inputs(3, &group);
  Eigen::VectorXd z(x.rows());
  for (Eigen::Index k = 0; k < x.rows(); ++k) {
    z(k) = 1.0 + 2.0 * x(k, 0) - 0.5 * x(k, 1) + 0.25 * x(k, 2) + 3.0 * x(k, 3);
  }
  // Every candidate that contains a first-order fit predicts held-out points exactly too; the
  // tie goes to the simplest.
  EXPECT_TRUE(choose_prior_shape(x, z, group, 18).first_order());
}

TEST(FnnPrior, AShapeWithMoreTermsThanHeldOutFitsCanPinIsNeverChosen) {
  // L9: each pair of inputs has one design point per cell; leaving one out leaves the pair's
  // quadratic (9 terms) with 8 points.
  constexpr int kL9[9][4] = {{0, 0, 0, 0},
                             {0, 1, 1, 1},
                             {0, 2, 2, 2},
                             {1, 0, 1, 2},
                             {1, 1, 2, 0},
                             {1, 2, 0, 1},
                             {2, 0, 2, 1},
                             {2, 1, 0, 2},
                             {2, 2, 1, 0}};
  Eigen::MatrixXd x(9, 4);
  std::vector<std::size_t> group;
  for (int run = 0; run < 9; ++run) {
    for (int i = 0; i < 4; ++i) x(run, i) = 0.5 * kL9[run][i];
    group.push_back(static_cast<std::size_t>(run));
  }
  Eigen::VectorXd z(x.rows());
  for (Eigen::Index k = 0; k < x.rows(); ++k) z(k) = bent(x(k, 0), x(k, 1));
  const PriorShape pair{{0, 1}, {}};
  EXPECT_TRUE(std::isinf(leave_one_point_out_sse(pair, x, z, group, 9)));
  EXPECT_NE(choose_prior_shape(x, z, group, 9).quadratic, (std::vector<int>{0, 1}));
}

TEST(FnnPrior, APartOfTheL18WithoutACellOfThePairCannotPinThePairOrChooseIt) {
  // The L18 runs every (PV, PD) cell twice; a CV fold without both runs of one cell, or a
  // held-out end with only two PV levels left, cannot determine the pair's quadratic, and a
  // shape chosen on that part must be one it can.
  std::vector<std::size_t> group;
  const Eigen::MatrixXd x = l18_inputs(3, &group);
  cmmcomp::detail::SplitMix64 rng{test::seed() + 4};
  Eigen::VectorXd z(x.rows());
  for (Eigen::Index k = 0; k < x.rows(); ++k) {
    z(k) = bent(x(k, 0), x(k, 1)) + 0.1 * rng.normal();
  }
  const PriorShape pair{{0, 1}, {}};
  const std::vector<Eigen::Index> all = all_rows(x.rows());
  EXPECT_TRUE(prior_identifiable(pair, x, all));
  std::vector<Eigen::Index> no_cell, no_high_pv;
  for (const Eigen::Index k : all) {
    if (!(x(k, 0) == 1.0 && x(k, 1) == 1.0)) no_cell.push_back(k);
    if (x(k, 0) < 1.0) no_high_pv.push_back(k);
  }
  ASSERT_LT(no_cell.size(), all.size());
  EXPECT_FALSE(prior_identifiable(pair, x, no_cell));
  EXPECT_FALSE(prior_identifiable(pair, x, no_high_pv));
  EXPECT_FALSE(prior_identifiable(PriorShape{{0}, {1, 2, 3}}, x, no_high_pv));
  EXPECT_TRUE(prior_identifiable(PriorShape{{1}, {0, 2, 3}}, x, no_high_pv));
  for (const auto* part : {&no_cell, &no_high_pv}) {
    const PriorShape chosen = choose_prior_shape(x, z, group, 18, *part);
    EXPECT_TRUE(prior_identifiable(chosen, x, *part)) << chosen.describe({});
    EXPECT_TRUE(std::isfinite(leave_one_point_out_sse(chosen, x, z, group, 18, *part)))
        << chosen.describe({});
  }
  // On all the data the pair is still the choice.
  EXPECT_EQ(choose_prior_shape(x, z, group, 18, all).quadratic, (std::vector<int>{0, 1}));
}

TEST(FnnPrior, OnTheL18AliasedPairsAreSettledByTheStrongestMainEffects) {
  // The L18 estimates main effects cleanly but aliases pair interactions: a response of inputs
  // a and b is fitted at all 18 moves by the quadratic over other pairs too, and between the
  // moves those aliases are wrong. Heredity allows only the pair of the two largest main
  // effects.
  std::vector<std::size_t> group;
  const Eigen::MatrixXd x = l18_inputs(3, &group);
  const std::vector<Eigen::Index> all = all_rows(x.rows());
  const std::vector<std::vector<int>> pairs = {{0, 2}, {0, 3}, {2, 3}};
  for (const std::vector<int>& pair : pairs) {
    Eigen::VectorXd z(x.rows());
    for (Eigen::Index k = 0; k < x.rows(); ++k) {
      const double a = x(k, pair[0]), b = x(k, pair[1]);
      z(k) = 4.0 * a * b + 2.0 * a * a;
    }
    int exact_fits = 0;
    for (const std::vector<int>& other : pairs) {
      const PriorShape shape{other, {}};
      if (leave_one_point_out_sse(shape, x, z, group, 18) < 1e-6) ++exact_fits;
      EXPECT_EQ(respects_heredity(shape, x, z, all), other == pair)
          << "response of " << pair[0] << "×" << pair[1] << ", shape " << shape.describe({});
    }
    EXPECT_EQ(exact_fits, 3) << "the aliasing this guards against is gone";
    EXPECT_EQ(choose_prior_shape(x, z, group, 18).quadratic, pair);
  }
}

}  // namespace
}  // namespace cmmcomp::training::detail
