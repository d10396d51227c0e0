// SPDX-License-Identifier: MIT
/// @file Main-effects ANOVA: a hand-checked example, partition properties, pooling, F conventions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/anova.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_seed.hpp"

namespace cmmcomp::doe {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Factors A and B on columns 0 and 1 of the L9:
//   run   1  2  3  4  5  6  7  8  9
//   A     0  0  0  1  1  1  2  2  2
//   B     0  1  2  0  1  2  0  1  2
//   y     2  4  6  5  7  6  8  9  7
// By hand: sum 54, grand mean 6; deviations -4 -2 0 -1 1 0 2 3 1 -> SS_T = 36, dof 8.
// A level means (2+4+6)/3 = 4, (5+7+6)/3 = 6, (8+9+7)/3 = 8 -> SS_A = 3*(4 + 0 + 4) = 24, dof 2.
// B level means (2+5+8)/3 = 5, (4+7+9)/3 = 20/3, (6+6+7)/3 = 19/3
//   -> SS_B = 3*(1 + 4/9 + 1/9) = 14/3, dof 2.
// Error SS_e = 36 - 24 - 14/3 = 22/3, dof 8 - 4 = 4, MS_e = 11/6.
// MS_A = 12 -> F_A = 12 / (11/6) = 72/11; MS_B = 7/3 -> F_B = (7/3) / (11/6) = 14/11.
// Weights: A 24/36 = 66.67 %, B (14/3)/36 = 12.96 %, error (22/3)/36 = 20.37 %.
Design hand_design() {
  return assign(taguchi_l9(), {Factor{"A", {1, 2, 3}}, Factor{"B", {1, 2, 3}}}, {0, 1});
}
const std::vector<double> kHandY{2, 4, 6, 5, 7, 6, 8, 9, 7};

TEST(Anova, HandCheckedL9Example) {
  const AnovaTable t = anova(hand_design(), kHandY);
  ASSERT_EQ(t.factors.size(), 2u);
  const AnovaRow& a = t.factor("A");
  const AnovaRow& b = t.factor("B");
  EXPECT_DOUBLE_EQ(t.grand_mean, 6.0);
  EXPECT_DOUBLE_EQ(t.total.sum_of_squares, 36.0);
  EXPECT_EQ(t.total.dof, 8);
  EXPECT_DOUBLE_EQ(a.sum_of_squares, 24.0);
  EXPECT_EQ(a.dof, 2);
  EXPECT_DOUBLE_EQ(a.mean_square, 12.0);
  EXPECT_DOUBLE_EQ(b.sum_of_squares, 14.0 / 3.0);
  EXPECT_EQ(b.dof, 2);
  EXPECT_DOUBLE_EQ(b.mean_square, 7.0 / 3.0);
  EXPECT_DOUBLE_EQ(t.error.sum_of_squares, 22.0 / 3.0);
  EXPECT_EQ(t.error.dof, 4);
  EXPECT_DOUBLE_EQ(t.error.mean_square, 11.0 / 6.0);
  EXPECT_DOUBLE_EQ(a.f_value, 72.0 / 11.0);
  EXPECT_DOUBLE_EQ(b.f_value, 14.0 / 11.0);
  EXPECT_TRUE(a.has_f);
  EXPECT_TRUE(b.has_f);
  EXPECT_FALSE(t.error.has_f);
  EXPECT_DOUBLE_EQ(a.weight_percent, 200.0 / 3.0);
  EXPECT_DOUBLE_EQ(b.weight_percent, 14.0 / 3.0 / 36.0 * 100.0);
  EXPECT_DOUBLE_EQ(t.error.weight_percent, 22.0 / 3.0 / 36.0 * 100.0);
  EXPECT_DOUBLE_EQ(t.total.weight_percent, 100.0);
  ASSERT_EQ(t.level_means.size(), 2u);
  EXPECT_DOUBLE_EQ(t.level_means[0][0], 4.0);
  EXPECT_DOUBLE_EQ(t.level_means[0][1], 6.0);
  EXPECT_DOUBLE_EQ(t.level_means[0][2], 8.0);
  EXPECT_DOUBLE_EQ(t.level_means[1][1], 20.0 / 3.0);
  EXPECT_FALSE(a.pooled);
  EXPECT_FALSE(b.pooled);
}

// Pooling B (12.96 % < 15 %) into the error: SS_e = 22/3 + 14/3 = 12, dof 6, MS_e = 2, F_A = 6.
TEST(Anova, HandCheckedPoolingByThresholdAndByName) {
  AnovaOptions by_threshold;
  by_threshold.pool_below_percent = 15.0;
  AnovaOptions by_name;
  by_name.pool_factors = {"B"};
  for (const AnovaOptions& opt : {by_threshold, by_name}) {
    const AnovaTable t = anova(hand_design(), kHandY, opt);
    const AnovaRow& a = t.factor("A");
    const AnovaRow& b = t.factor("B");
    EXPECT_FALSE(a.pooled);
    EXPECT_TRUE(b.pooled);
    EXPECT_FALSE(b.has_f);
    EXPECT_EQ(b.f_value, 0.0);
    EXPECT_DOUBLE_EQ(b.sum_of_squares, 14.0 / 3.0);  // its own row keeps its SS
    EXPECT_DOUBLE_EQ(t.error.sum_of_squares, 12.0);
    EXPECT_EQ(t.error.dof, 6);
    EXPECT_DOUBLE_EQ(t.error.mean_square, 2.0);
    EXPECT_DOUBLE_EQ(a.f_value, 6.0);
    EXPECT_DOUBLE_EQ(a.weight_percent + t.error.weight_percent, 100.0);
  }
}

std::vector<double> random_responses(std::mt19937_64& rng, std::size_t n) {
  std::vector<double> y(n);
  for (double& v : y) v = 10.0 + static_cast<double>(rng() >> 11) * 0x1.0p-53 * 5.0;
  return y;
}

double weight_sum(const AnovaTable& t) {
  double sum = t.error.weight_percent;
  for (const auto& row : t.factors) sum += row.pooled ? 0.0 : row.weight_percent;
  return sum;
}

TEST(Anova, PaperL18PartitionsTheTotal) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed());
  const Design d = paper_l18_design();
  const int cases = test::soak_count(50);
  for (int k = 0; k < cases; ++k) {
    const std::vector<double> y = random_responses(rng, 18);
    const AnovaTable t = anova(d, y);
    EXPECT_EQ(t.total.dof, 17);
    EXPECT_EQ(t.error.dof, 9);  // 17 - 4 * 2
    double ss = t.error.sum_of_squares;
    for (const auto& row : t.factors) {
      EXPECT_EQ(row.dof, 2);
      EXPECT_GE(row.sum_of_squares, 0.0);
      EXPECT_TRUE(std::isfinite(row.f_value));
      EXPECT_NEAR(row.f_value, row.mean_square / t.error.mean_square, 1e-12 * row.f_value);
      ss += row.sum_of_squares;
    }
    EXPECT_NEAR(ss, t.total.sum_of_squares, 1e-12 * t.total.sum_of_squares);
    EXPECT_NEAR(weight_sum(t), 100.0, 1e-9);
    EXPECT_GE(t.error.sum_of_squares, 0.0);
  }
}

// Saturated designs (every dof used by a factor): the factor SS alone make up the total.
TEST(Anova, SaturatedDesignHasNoErrorDofAndNoF) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 1);
  std::vector<Factor> f9;
  for (int i = 0; i < 4; ++i) f9.push_back(Factor{"F" + std::to_string(i), {1, 2, 3}});
  std::vector<Factor> f27;
  for (int i = 0; i < 13; ++i) f27.push_back(Factor{"G" + std::to_string(i), {1, 2, 3}});
  const Design l9 = assign(taguchi_l9(), f9, {0, 1, 2, 3});
  std::vector<int> cols27(13);
  for (int i = 0; i < 13; ++i) cols27[static_cast<std::size_t>(i)] = i;
  const Design l27 = assign(taguchi_l27(), f27, cols27);
  const int cases = test::soak_count(20);
  for (int k = 0; k < cases; ++k) {
    for (const Design* d : {&l9, &l27}) {
      const std::vector<double> y = random_responses(rng, static_cast<std::size_t>(d->runs()));
      const AnovaTable t = anova(*d, y);
      EXPECT_EQ(t.error.dof, 0);
      EXPECT_EQ(t.error.sum_of_squares, 0.0);  // rounding noise reported as 0
      double ss = 0.0;
      for (const auto& row : t.factors) {
        EXPECT_FALSE(row.has_f);
        EXPECT_EQ(row.f_value, 0.0);
        ss += row.sum_of_squares;
      }
      EXPECT_NEAR(ss, t.total.sum_of_squares, 1e-12 * t.total.sum_of_squares);
      EXPECT_NEAR(weight_sum(t), 100.0, 1e-9);

      // Taguchi pooling: the smallest factor goes into the error and F values appear.
      AnovaOptions opt;
      opt.pool_smallest_when_saturated = true;
      const AnovaTable p = anova(*d, y, opt);
      EXPECT_EQ(p.error.dof, 2);
      const auto smallest = std::min_element(
          t.factors.begin(), t.factors.end(), [](const AnovaRow& x, const AnovaRow& z) {
            return x.sum_of_squares < z.sum_of_squares;
          });
      const AnovaRow& pooled = p.factor(smallest->source);
      EXPECT_TRUE(pooled.pooled);
      EXPECT_DOUBLE_EQ(p.error.sum_of_squares, pooled.sum_of_squares);
      for (const auto& row : p.factors) {
        EXPECT_EQ(row.pooled, row.source == pooled.source);
        EXPECT_EQ(row.has_f, !row.pooled);
        if (row.has_f) {
          EXPECT_GE(row.f_value, 1.0);  // every other factor is at least as big
        }
      }
      EXPECT_NEAR(weight_sum(p), 100.0, 1e-9);
    }
  }
}

TEST(Anova, PoolingMovesSmallFactorsIntoError) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 2);
  const Design d = paper_l18_design();
  const int cases = test::soak_count(50);
  for (int k = 0; k < cases; ++k) {
    const std::vector<double> y = random_responses(rng, 18);
    const AnovaTable plain = anova(d, y);
    std::vector<double> w;
    for (const auto& row : plain.factors) w.push_back(row.weight_percent);
    std::sort(w.begin(), w.end());
    AnovaOptions opt;
    opt.pool_below_percent = 0.5 * (w[1] + w[2]);  // pools the two smallest
    const AnovaTable p = anova(d, y, opt);
    double moved_ss = 0.0;
    int moved_dof = 0;
    int pooled_count = 0;
    for (std::size_t i = 0; i < p.factors.size(); ++i) {
      const AnovaRow& row = p.factors[i];
      EXPECT_EQ(row.pooled, plain.factors[i].weight_percent < opt.pool_below_percent);
      EXPECT_DOUBLE_EQ(row.sum_of_squares, plain.factors[i].sum_of_squares);
      if (row.pooled) {
        ++pooled_count;
        moved_ss += row.sum_of_squares;
        moved_dof += row.dof;
        EXPECT_FALSE(row.has_f);
      } else {
        EXPECT_NEAR(row.f_value, row.mean_square / p.error.mean_square, 1e-12 * row.f_value);
      }
    }
    EXPECT_EQ(pooled_count, 2);
    EXPECT_EQ(p.error.dof, plain.error.dof + moved_dof);
    EXPECT_NEAR(p.error.sum_of_squares,
                plain.error.sum_of_squares + moved_ss,
                1e-12 * p.total.sum_of_squares);
    EXPECT_NEAR(weight_sum(p), 100.0, 1e-9);
  }
}

TEST(Anova, ResponseOfOneFactorGivesItAllTheWeight) {
  const Design d = paper_l18_design();
  const int pv = d.factor_index("PV");
  std::vector<double> y;
  for (int r = 0; r < d.runs(); ++r)
    y.push_back(std::vector<double>{10, 20, 40}[static_cast<std::size_t>(d.level(r, pv))]);
  const AnovaTable t = anova(d, y);
  EXPECT_DOUBLE_EQ(t.factor("PV").weight_percent, 100.0);
  EXPECT_EQ(t.error.sum_of_squares, 0.0);
  EXPECT_EQ(t.error.dof, 9);
  EXPECT_EQ(t.factor("PV").f_value, kInf);  // documented: MS_e == 0 and MS > 0 -> +inf
  for (const char* other : {"PD", "AV", "AD"}) {
    EXPECT_EQ(t.factor(other).sum_of_squares, 0.0) << other;
    EXPECT_EQ(t.factor(other).f_value, 0.0) << other;  // MS == 0 -> 0, not NaN
    EXPECT_TRUE(t.factor(other).has_f);
  }

  // With a little noise on top, the weight is ~100 % and F is finite and huge.
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 3);
  const std::vector<double> noise = random_responses(rng, 18);
  for (std::size_t r = 0; r < y.size(); ++r) y[r] += 1e-3 * noise[r];
  const AnovaTable n = anova(d, y);
  EXPECT_GT(n.factor("PV").weight_percent, 99.99);
  EXPECT_TRUE(std::isfinite(n.factor("PV").f_value));
  EXPECT_GT(n.factor("PV").f_value, 1e5);
}

TEST(Anova, ConstantResponseGivesZerosNotNaN) {
  const AnovaTable t = anova(paper_l18_design(), std::vector<double>(18, 7.5));
  EXPECT_DOUBLE_EQ(t.grand_mean, 7.5);
  EXPECT_EQ(t.total.sum_of_squares, 0.0);
  EXPECT_EQ(t.total.weight_percent, 0.0);
  EXPECT_EQ(t.error.weight_percent, 0.0);
  for (const auto& row : t.factors) {
    EXPECT_EQ(row.sum_of_squares, 0.0);
    EXPECT_EQ(row.weight_percent, 0.0);
    EXPECT_EQ(row.f_value, 0.0);
  }
}

// Replicates add error dof; the factor SS of the 54 samples are 3x those of the 18 means.
TEST(Anova, ReplicatedDesignAndAveragedDesignAgree) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 4);
  const Design rep = replicate(paper_l18_design(), 3);
  const std::vector<double> y = random_responses(rng, 54);
  const AnovaTable full = anova(rep, y);
  EXPECT_EQ(full.total.dof, 53);
  EXPECT_EQ(full.error.dof, 45);
  const ReplicateAverage avg = average_replicates(rep, y);
  const AnovaTable means = anova(avg.design, avg.means);
  EXPECT_EQ(means.error.dof, 9);
  for (std::size_t f = 0; f < 4; ++f) {
    EXPECT_NEAR(full.factors[f].sum_of_squares,
                3.0 * means.factors[f].sum_of_squares,
                1e-12 * full.total.sum_of_squares);
    for (std::size_t l = 0; l < 3; ++l) {
      EXPECT_NEAR(full.level_means[f][l], means.level_means[f][l], 1e-12);
    }
  }
}

// Table 4 of the paper, re-derived from its weights (weights are SS shares: SS_T = 100). Its F
// values are consistent with PD having 1 dof and the error 10 dof (F_PD = 10 w/w_e, the others
// 5 w/w_e), i.e. PD on the 2-level column; with the project's 3-level PD (error dof 9) every
// F would be 4.5 w/w_e instead. Tolerance: the published weights have 2-3 significant digits.
TEST(Anova, PaperTable4FValuesFollowFromItsWeights) {
  struct Column {
    double w[4];  // PD, PV, AD, AV
    double error;
    double f[4];
  };
  const Column table4[4] = {
      {{0.28, 91.6, 1.15, 1.77}, 5.19, {0.54, 88.3, 1.11, 1.71}},   // MPE
      {{13.6, 79.1, 0.01, 2.4}, 4.89, {27.85, 80.86, 0.010, 2.5}},  // RPE
      {{0.49, 2.32, 3.25, 82.1}, 11.8, {0.42, 0.98, 1.38, 34.7}},   // MAE
      {{0.80, 0.70, 29.1, 61.8}, 7.6, {1.05, 0.46, 19.2, 40.4}},    // RAE
  };
  const std::vector<std::string> names{"PD", "PV", "AD", "AV"};
  for (const Column& c : table4) {
    const std::vector<double> ss(c.w, c.w + 4);
    const double total = c.w[0] + c.w[1] + c.w[2] + c.w[3] + c.error;
    const AnovaTable t = anova_from_sums_of_squares(names, ss, {1, 2, 2, 2}, total, 17);
    EXPECT_EQ(t.error.dof, 10);
    for (std::size_t i = 0; i < 4; ++i) {
      EXPECT_NEAR(t.factors[i].f_value, c.f[i], 0.03 * c.f[i] + 0.001) << names[i];
    }
    EXPECT_NEAR(t.error.weight_percent, 100.0 * c.error / total, 1e-9);
    const AnovaTable project = anova_from_sums_of_squares(names, ss, {2, 2, 2, 2}, total, 17);
    EXPECT_EQ(project.error.dof, 9);
    EXPECT_GT(std::fabs(project.factors[1].f_value - c.f[1]), 0.05 * c.f[1]);  // PV no match
  }
}

TEST(Anova, RejectsBadInput) {
  const Design d = hand_design();
  EXPECT_THROW(anova(d, std::vector<double>(8, 1.0)), cmmcomp::ConfigError);
  std::vector<double> y = kHandY;
  y[3] = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(anova(d, y), cmmcomp::ConfigError);
  EXPECT_THROW(anova(latin_hypercube({"a"}, {0}, {1}, 9, 1), kHandY), cmmcomp::ConfigError);

  AnovaOptions bad;
  bad.pool_below_percent = -1.0;
  EXPECT_THROW(anova(d, kHandY, bad), cmmcomp::ConfigError);
  AnovaOptions unknown;
  unknown.pool_factors = {"Z"};
  EXPECT_THROW(anova(d, kHandY, unknown), cmmcomp::ConfigError);

  // A missing run unbalances A.
  Design missing = d;
  missing.values.pop_back();
  missing.level_indices.pop_back();
  missing.run_index.pop_back();
  try {
    anova(missing, std::vector<double>(8, 1.0));
    ADD_FAILURE() << "no exception";
  } catch (const cmmcomp::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("not balanced"), std::string::npos) << e.what();
  }
  // Both factors balanced, but not orthogonal to each other.
  Design skew = d;
  // Run 1 (A0, B0) and run 5 (A1, B1) trade B: (A0, B1) twice, (A0, B0) never.
  std::swap(skew.level_indices[0][1], skew.level_indices[4][1]);
  try {
    anova(skew, kHandY);
    ADD_FAILURE() << "no exception";
  } catch (const cmmcomp::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("'A' and 'B' are not orthogonal"), std::string::npos)
        << e.what();
  }
  // SS-only form: factors exceeding the total, bad dof.
  EXPECT_THROW(anova_from_sums_of_squares({"a"}, {2.0}, {1}, 1.0, 3), cmmcomp::ConfigError);
  EXPECT_THROW(anova_from_sums_of_squares({"a"}, {0.5}, {0}, 1.0, 3), cmmcomp::ConfigError);
  EXPECT_THROW(anova_from_sums_of_squares({"a"}, {0.5}, {4}, 1.0, 3), cmmcomp::ConfigError);
  EXPECT_THROW(AnovaTable{}.factor("x"), cmmcomp::ConfigError);
}

TEST(Anova, FormatsATable) {
  AnovaOptions opt;
  opt.pool_factors = {"B"};
  const std::string text = format_anova_table(anova(hand_design(), kHandY, opt));
  EXPECT_NE(text.find("source"), std::string::npos) << text;
  EXPECT_NE(text.find("weight %"), std::string::npos) << text;
  EXPECT_NE(text.find("pooled"), std::string::npos) << text;
  EXPECT_NE(text.find("error"), std::string::npos) << text;
  EXPECT_NE(text.find("total"), std::string::npos) << text;
  EXPECT_NE(text.find("66.67"), std::string::npos) << text;  // A's weight
  EXPECT_NE(text.find(" 6\n"), std::string::npos) << text;   // F_A after pooling B
  std::vector<double> y;
  for (int r = 0; r < 9; ++r) y.push_back(r / 3);
  EXPECT_NE(format_anova_table(anova(hand_design(), y)).find("inf"), std::string::npos);
}

}  // namespace
}  // namespace cmmcomp::doe
