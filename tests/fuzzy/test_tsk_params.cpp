// SPDX-License-Identifier: MIT
/// @file Parameter layout of the T-S network: counts, offsets, rule numbering, accessors.
#include <gtest/gtest.h>

#include <array>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/fuzzy/tsk_params.hpp>
#include <set>

namespace cmmcomp::fuzzy {
namespace {

using Paper = TskLayout<4, 3, 1>;
using PaperMulti = TskLayout<4, 3, 4>;

TEST(TskLayout, PaperCountsAreCompileTimeConstants) {
  static_assert(Paper::kRules == 81);
  static_assert(Paper::kTerms == 5);
  static_assert(Paper::kParamCount == 429);
  static_assert(PaperMulti::kParamCount == 2 * 4 * 3 + 4 * 81 * 5);
  static_assert(TskLayout<1, 1, 1>::kRules == 1);
  static_assert(TskLayout<2, 5, 3>::kRules == 25);
  static_assert(TskLayout<2, 5, 3>::kParamCount == 2 * 2 * 5 + 3 * 25 * 3);
  static_assert(PaperNetwork::kParamCount == 429);
  static_assert(TskModel<double, 4, 3, 4>::kRules == 81);
  static_assert(std::tuple_size_v<decltype(PaperNetwork::Params::values)> == 429);
  SUCCEED();
}

TEST(TskLayout, RuntimeLayoutIsTheSameArithmetic) {
  static_assert(RuntimeLayout{4, 3, 4}.param_count() == PaperMulti::kParamCount);
  static_assert(RuntimeLayout{5, 3, 4}.rules() == 243);
  const RuntimeLayout r = PaperMulti::kRuntime;
  for (int i = 0; i < 4; ++i) {
    for (int set = 0; set < 3; ++set) {
      EXPECT_EQ(r.centre_index(i, set), PaperMulti::centre_index(i, set));
      EXPECT_EQ(r.width_index(i, set), PaperMulti::width_index(i, set));
    }
  }
  EXPECT_EQ(r.consequent_index(3, 80, 4), PaperMulti::consequent_index(3, 80, 4));
  EXPECT_EQ(r.consequent_index(3, 80, 4), PaperMulti::kParamCount - 1);
}

TEST(TskLayout, BlocksAreContiguousAndInOrder) {
  // Centres and widths set-major: [set][input].
  EXPECT_EQ(Paper::centre_index(0, 0), 0);
  EXPECT_EQ(Paper::centre_index(1, 0), 1);
  EXPECT_EQ(Paper::centre_index(0, 2), 8);
  EXPECT_EQ(Paper::centre_index(3, 2), 11);
  EXPECT_EQ(Paper::width_index(0, 0), 12);
  EXPECT_EQ(Paper::width_index(3, 0), 15);
  EXPECT_EQ(Paper::width_index(3, 2), 23);
  // Consequents rule-major: [rule][output][term].
  EXPECT_EQ(Paper::consequent_index(0, 0, 0), 24);
  EXPECT_EQ(Paper::consequent_index(0, 0, 4), 28);
  EXPECT_EQ(Paper::consequent_index(0, 1, 0), 29);
  EXPECT_EQ(Paper::consequent_index(0, 80, 4), 428);
  EXPECT_EQ(PaperMulti::kRuleBlock, 20);
  EXPECT_EQ(PaperMulti::consequent_index(1, 0, 0), 24 + 5);
  EXPECT_EQ(PaperMulti::consequent_index(0, 1, 0), 24 + 20);
  EXPECT_EQ(PaperMulti::consequent_index(3, 80, 4), PaperMulti::kParamCount - 1);
  // Every index is used exactly once.
  std::set<int> seen;
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      seen.insert(PaperMulti::centre_index(i, s));
      seen.insert(PaperMulti::width_index(i, s));
    }
  }
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < 81; ++j) {
      for (int k = 0; k < 5; ++k) seen.insert(PaperMulti::consequent_index(o, j, k));
    }
  }
  EXPECT_EQ(static_cast<int>(seen.size()), PaperMulti::kParamCount);
  EXPECT_EQ(*seen.begin(), 0);
  EXPECT_EQ(*seen.rbegin(), PaperMulti::kParamCount - 1);
}

TEST(TskLayout, RuleDigitsHaveInputZeroMostSignificant) {
  EXPECT_EQ(Paper::rule_index({0, 0, 0, 0}), 0);
  EXPECT_EQ(Paper::rule_index({0, 0, 0, 1}), 1);
  EXPECT_EQ(Paper::rule_index({0, 0, 1, 0}), 3);
  EXPECT_EQ(Paper::rule_index({1, 0, 0, 0}), 27);
  EXPECT_EQ(Paper::rule_index({2, 2, 2, 2}), 80);
  EXPECT_EQ(Paper::rule_set(1, 3), 1);
  EXPECT_EQ(Paper::rule_set(27, 0), 1);
  EXPECT_EQ(Paper::rule_set(27, 3), 0);
  for (int j = 0; j < Paper::kRules; ++j) {
    std::array<int, 4> sets{};
    for (int i = 0; i < 4; ++i) sets[static_cast<unsigned>(i)] = Paper::rule_set(j, i);
    EXPECT_EQ(Paper::rule_index(sets), j);
  }
  static_assert(TskLayout<3, 4, 1>::rule_index({3, 2, 1}) == 3 * 16 + 2 * 4 + 1);
}

TEST(TskParams, AccessorsAddressTheFlatBlock) {
  TskParams<double, 4, 3, 2> p;
  for (std::size_t k = 0; k < p.values.size(); ++k) p.values[k] = static_cast<double>(k);
  EXPECT_EQ(p.centre(2, 1), 6.0);  // set 1, input 2: 1·4 + 2
  EXPECT_EQ(p.width(2, 1), 18.0);  // 12 + 6
  EXPECT_EQ(p.consequent(1, 3, 2), static_cast<double>(24 + (3 * 2 + 1) * 5 + 2));
  p.consequent(1, 3, 2) = -1.0;
  EXPECT_EQ(p.values[24 + 37], -1.0);
  EXPECT_EQ(p.data(), p.values.data());
  const auto& cp = p;
  EXPECT_EQ(cp.centre(3, 2), 11.0);
  EXPECT_EQ(cp.data()[12], cp.width(0, 0));
}

}  // namespace
}  // namespace cmmcomp::fuzzy
