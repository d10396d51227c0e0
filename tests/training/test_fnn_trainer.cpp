// SPDX-License-Identifier: MIT
/// @file Tests of train_fnn as a whole (training/fnn_trainer.hpp): determinism and the input-set
/// entry.
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

namespace cmmcomp::training {
namespace {

using namespace fnn_test;

// --- Determinism -----------------------------------------------------------------------------

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

TEST(FnnTrainer, TrainNetworkIsTrainFnnOnTheInputSetWithItsNames) {
  const Rows<4> x = paper_l18_inputs(1);
  std::vector<DatasetRow> rows;
  Rows<4> targets;
  for (const auto& v : x) {
    DatasetRow r;
    r.pv_mm_s = v[0];
    r.pd_mm = v[1];
    r.av_mm_s = v[2];
    r.ad_mm = v[3];
    r.mpe_um = 0.01 * v[0] + 0.2 * v[3];
    r.rpe_um = -0.003 * v[1] * v[0] / 100.0;
    r.mae_um = 0.5 * v[2];
    r.rae_um = 1.0;
    rows.push_back(r);
    targets.push_back(gather_errors(r));
  }
  FnnTrainingOptions options;
  options.interval_coverage = 0.0;
  const TrainedNetwork<PaperInputs> net = train_network<PaperInputs>(rows, options);
  ASSERT_TRUE(net.summary.usable());
  // The prior names the set's inputs, not x0…x3.
  for (const std::string& p : net.summary.prior) {
    EXPECT_EQ(p.find("x0"), std::string::npos) << p;
  }
  options.input_names = input_labels<PaperInputs>();
  const auto direct = train_fnn<4, 3, 4>(x, targets, options);
  const fuzzy::TskModel<double, 4, 3, 4>& served = net.model;
  EXPECT_TRUE(bit_identical(served, direct.model));
  EXPECT_EQ(net.summary.prior, direct.summary.prior);
}

}  // namespace
}  // namespace cmmcomp::training
