// SPDX-License-Identifier: MIT
/// @file The held-out check's verdict (issue 36 §3): each reduction against the paper's Table 5,
/// each coverage against its nominal within ±3 points or the sample count's binomial 2σ band.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/training/evaluation.hpp>

namespace cmmcomp::training {
namespace {

std::array<Table5Row, 4> table_with_reductions(const std::array<double, 4>& reductions) {
  std::array<Table5Row, 4> t{};
  for (std::size_t o = 0; o < 4; ++o) t[o].reduction_pct = reductions[o];
  return t;
}

TEST(HeldOutCheck, EveryReductionAndCoverageMetPasses) {
  const auto c =
      held_out_check(table_with_reductions({95, 95, 95, 95}), {95.0, 94.0, 96.5, 92.5}, 95.0, 1000);
  EXPECT_TRUE(c.passed) << c.missed;
  EXPECT_TRUE(c.missed.empty());
  EXPECT_DOUBLE_EQ(c.coverage_band_pct, 3.0);
}

TEST(HeldOutCheck, EachMissIsNamed) {
  const auto c =
      held_out_check(table_with_reductions({95, paper::kTable5Reduction[1] - 0.1, 95, 95}),
                     {95.0, 95.0, 95.0, 88.0},
                     95.0,
                     1000);
  EXPECT_FALSE(c.passed);
  EXPECT_FALSE(c.parameters[1].reduction_met);
  EXPECT_FALSE(c.parameters[3].coverage_met);
  EXPECT_NE(c.missed.find("RPE reduction 90.7 % < 90.8 %"), std::string::npos) << c.missed;
  EXPECT_NE(c.missed.find("RAE coverage 88.0 % outside 92.0–98.0 %"), std::string::npos)
      << c.missed;
  EXPECT_EQ(c.missed.find("MPE"), std::string::npos);
}

TEST(HeldOutCheck, ASmallCampaignGetsItsBinomialBandAndTooWideFailsToo) {
  // 60 samples at 95 %: 2·√(0.95·0.05/60) = 5.63 points.
  auto c = held_out_check(table_with_reductions({95, 95, 95, 95}), {90.0, 95, 95, 95}, 95.0, 60);
  EXPECT_NEAR(c.coverage_band_pct, 5.63, 0.01);
  EXPECT_TRUE(c.passed) << c.missed;
  // An interval that covers everything is too wide: it fails at 1000 samples.
  c = held_out_check(table_with_reductions({95, 95, 95, 95}), {100.0, 95, 95, 95}, 95.0, 1000);
  EXPECT_FALSE(c.passed);
  // No interval at all fails the coverage check.
  c = held_out_check(table_with_reductions({95, 95, 95, 95}), {NAN, 95, 95, 95}, 95.0, 1000);
  EXPECT_FALSE(c.passed);
  EXPECT_NE(c.missed.find("MPE has no interval"), std::string::npos) << c.missed;
}

}  // namespace
}  // namespace cmmcomp::training
