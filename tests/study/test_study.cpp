// SPDX-License-Identifier: MIT
/// @file The study layer (docs/study.md): targets and their one check with its known-unmet list,
/// limits built from the paper's constants, and recipes read strictly.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <string>
#include <vector>

namespace cmmcomp::study {
namespace {

std::vector<Target> two_targets(double reduction, double residual) {
  return {{"a_reduction", reduction, 90.0, Target::Kind::kAtLeast, "%"},
          {"a_residual", residual, 0.5, Target::Kind::kAtMost, "um"}};
}

TEST(StudyAcceptance, MetMissedAndKnownUnmet) {
  std::vector<Target> t = two_targets(91.0, 0.4);
  EXPECT_TRUE(check(t, {}).passed);
  t = two_targets(89.0, 0.4);
  Verdict v = check(t, {});
  ASSERT_FALSE(v.passed);
  ASSERT_EQ(v.failures.size(), 1u);
  EXPECT_NE(v.failures[0].find("a_reduction: 89 % misses >= 90 %"), std::string::npos)
      << v.failures[0];
  // Listed and still unmet: passes, marked.
  t = two_targets(91.0, 0.6);
  v = check(t, {"a_residual"});
  EXPECT_TRUE(v.passed);
  EXPECT_TRUE(t[1].known_unmet);
  // Listed and now met: the list is out of date.
  t = two_targets(91.0, 0.4);
  v = check(t, {"a_residual"});
  ASSERT_FALSE(v.passed);
  EXPECT_NE(v.failures[0].find("listed as known unmet, but now met"), std::string::npos);
  // Listed and not measured: a stale list.
  t = two_targets(91.0, 0.4);
  v = check(t, {"b_residual"});
  ASSERT_FALSE(v.passed);
  EXPECT_NE(v.failures[0].find("b_residual: listed as known unmet, but not measured"),
            std::string::npos);
}

TEST(StudyAcceptance, TheListFormat) {
  const KnownUnmet k = parse_known_unmet("# why\n\n  x: rpe_residual  \n#y\ny\n");
  EXPECT_EQ(k, (KnownUnmet{"x: rpe_residual", "y"}));
}

TEST(StudyAcceptance, LimitsComeFromThePaper) {
  // The mean |N(0, σ)| is √(2/π) σ: Table 1's σ of RPE 0.461 µm gives 0.3678 µm.
  EXPECT_NEAR(noise_floor_um(1), 0.461 * std::sqrt(2.0 / 3.14159265358979323846), 1e-12);
  std::array<training::Table5Row, kErrorCount> table{};
  for (auto& row : table) {
    row.reduction_pct = 95.0;
    row.mean_after = 0.1;
  }
  std::vector<Target> t = table5_targets("p: ", table, true);
  ASSERT_EQ(t.size(), 8u);
  EXPECT_EQ(t[0].name, "p: mpe_reduction");
  EXPECT_EQ(t[0].limit, paper::kTable5Reduction[0]);
  EXPECT_EQ(t[3].name, "p: rpe_residual");
  EXPECT_DOUBLE_EQ(t[3].limit, 1.5 * noise_floor_um(1));
  EXPECT_EQ(table5_targets("p: ", table, false).size(), 4u);
}

const char* kRecipe = R"(format_version = 1
description = "test"
inputs = "pv,pd,av,ad"
cases = [[1, 2], [11, 12]]

[[training]]
design = "l18"
repeats = 3
seed = 1

[test]
design = "lhs"
samples = 30
seeds = [2, 4]

[fit]
seed = 7
interval_folds = "ridge"

[acceptance]
reduction = false
)";

std::string error_of(const std::string& text) {
  try {
    parse_recipe(text, "r.toml", ".");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

std::string with(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

TEST(StudyRecipe, ParsesEveryKey) {
  const Recipe r = parse_recipe(kRecipe, "r.toml", ".");
  ASSERT_EQ(r.training.size(), 1u);
  EXPECT_EQ(r.training[0].design, "l18");
  EXPECT_EQ(r.training[0].repeats, 3);
  EXPECT_EQ(r.test.design, "lhs");
  EXPECT_EQ(r.test.samples, 30);
  EXPECT_EQ(r.test.seed, 2u);
  EXPECT_EQ(r.test_seeds, (std::vector<std::uint64_t>{2, 4}));
  EXPECT_EQ(r.fit.seed, 7u);
  EXPECT_EQ(*r.fit.interval_folds, "ridge");
  EXPECT_FALSE(r.fit.max_iterations);
  ASSERT_EQ(r.cases.size(), 2u);
  EXPECT_EQ(r.cases[1].first, 11u);
  EXPECT_FALSE(r.acceptance.reduction);
  EXPECT_EQ(r.machine, "default");
  EXPECT_EQ(r.levels, "pv=40,70,100;pd=40,60,80;av=8,12,16;ad=5,10,15");
}

TEST(StudyRecipe, RefusesWhatItDoesNotKnow) {
  EXPECT_NE(error_of(with(kRecipe, "format_version = 1", "format_version = 2"))
                .find("r.toml: format_version: must be 1"),
            std::string::npos);
  EXPECT_NE(error_of(with(kRecipe, "seed = 7", "seed = 7\nsed = 1")).find("fit.sed: unknown key"),
            std::string::npos);
  EXPECT_NE(error_of(with(kRecipe, "repeats = 3", "repeats = 0")).find("training[0].repeats"),
            std::string::npos);
  EXPECT_NE(error_of(with(kRecipe, "seeds = [2, 4]", "seeds = []")).find("test.seeds"),
            std::string::npos);
  EXPECT_NE(error_of(with(kRecipe, "\"ridge\"", "\"wide\"")).find("fit.interval_folds"),
            std::string::npos);
  EXPECT_NE(error_of(with(kRecipe, "[[1, 2], [11, 12]]", "[[1, 2, 3]]")).find("cases"),
            std::string::npos);
  EXPECT_NE(error_of(with(kRecipe, "design = \"l18\"", "design = \"l17\"")), "");
  EXPECT_NE(error_of(with(kRecipe, "[test]", "[tests]")), "");
  EXPECT_NE(error_of("format_version = 1\n[test\n").find("TOML syntax error"), std::string::npos);
}

TEST(StudyRecipe, TheShippedRecipesLoad) {
  for (const char* name : {"default-model", "default-y-model", "paper-l18"}) {
    const Recipe r =
        load_recipe(std::string(CMMCOMP_SOURCE_DIR) + "/data/recipes/" + name + ".toml");
    EXPECT_EQ(r.name, name);
    EXPECT_FALSE(r.training.empty());
  }
  const Recipe v =
      load_recipe(std::string(CMMCOMP_SOURCE_DIR) + "/data/recipes/paper-l18-mode-20.toml");
  EXPECT_EQ(recipe_machine(v).parameters.mode_frequency_hz,
            dynamics::load_machine(std::string(CMMCOMP_SOURCE_DIR) +
                                   "/data/machines/variant-mode-20.toml")
                .parameters.mode_frequency_hz);
}

}  // namespace
}  // namespace cmmcomp::study
