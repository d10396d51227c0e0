// SPDX-License-Identifier: MIT
/// @file Designs: factor assignment, full factorial, Latin hypercube, replication.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/doe/anova.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstdint>
#include <limits>
#include <random>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

#include "support/test_seed.hpp"

namespace cmmcomp::doe {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// Expects `fn` to throw cmmcomp::ConfigError whose message contains `part`.
template <typename Fn>
void expect_invalid(Fn fn, const std::string& part) {
  try {
    fn();
    ADD_FAILURE() << "no exception; expected one mentioning '" << part << "'";
  } catch (const cmmcomp::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

TEST(Assign, PaperL18PutsPvPdAvAdOnColumnsC2ToC5) {
  const OrthogonalArray oa = taguchi_l18();
  const std::vector<Factor> factors = paper_table3_factors();
  const Design d = assign(oa, factors, paper_l18_assignment());
  EXPECT_EQ(paper_l18_assignment(), (std::vector<int>{1, 2, 3, 4}));
  ASSERT_EQ(d.runs(), 18);
  ASSERT_EQ(d.factors(), 4);
  EXPECT_EQ(d.factor_names, (std::vector<std::string>{"PV", "PD", "AV", "AD"}));
  EXPECT_TRUE(d.has_levels);
  EXPECT_EQ(d.level_counts, (std::vector<int>{3, 3, 3, 3}));
  std::string why;
  EXPECT_TRUE(d.is_valid(&why)) << why;
  for (int r = 0; r < 18; ++r) {
    EXPECT_EQ(d.run_index[static_cast<std::size_t>(r)], r);
    for (int f = 0; f < 4; ++f) {
      const int l = oa.level(r, f + 1);
      EXPECT_EQ(d.level(r, f), l);
      EXPECT_EQ(d.value(r, f),
                factors[static_cast<std::size_t>(f)].levels[static_cast<std::size_t>(l)]);
    }
  }
  // Run 4 of the CSV is "1,2,1,1,2,...": PV 70 mm/s, PD 40 mm, AV 8 mm/s, AD 10 mm.
  EXPECT_EQ(d.value(3, d.factor_index("PV")), 0.070);
  EXPECT_EQ(d.value(3, d.factor_index("PD")), 0.040);
  EXPECT_EQ(d.value(3, d.factor_index("AV")), 0.008);
  EXPECT_EQ(d.value(3, d.factor_index("AD")), 0.010);
  // The convenience function gives the same design.
  EXPECT_EQ(paper_l18_design().values, d.values);
}

TEST(Assign, TwoLevelFactorFitsColumnZeroOfL18) {
  const Design d = assign(taguchi_l18(), {Factor{"dir", {-1.0, 1.0}}}, {0});
  ASSERT_EQ(d.runs(), 18);
  EXPECT_EQ(d.value(0, 0), -1.0);
  EXPECT_EQ(d.value(17, 0), 1.0);
}

TEST(Assign, RejectsLevelCountMismatchNamingTheFactor) {
  const std::vector<Factor> factors{Factor{"PV", {1, 2, 3}}, Factor{"PD", {1, 2}}};
  expect_invalid([&] { assign(taguchi_l18(), factors, {1, 2}); }, "'PD'");
  // The 3-level PV on the 2-level column c1.
  expect_invalid([&] { assign(taguchi_l18(), {factors[0]}, {0}); }, "'PV'");
}

TEST(Assign, RejectsColumnUsedTwiceOrOutOfRange) {
  const Factor a{"A", {1, 2, 3}};
  const Factor b{"B", {4, 5, 6}};
  expect_invalid([&] { assign(taguchi_l9(), {a, b}, {1, 1}); }, "already used");
  expect_invalid([&] { assign(taguchi_l9(), {a, b}, {0, 4}); }, "outside");
  expect_invalid([&] { assign(taguchi_l9(), {a, b}, {-1, 0}); }, "outside");
  expect_invalid([&] { assign(taguchi_l9(), {a, b}, {0}); }, "columns");
  expect_invalid([&] { assign(taguchi_l9(), {}, {}); }, "no factors");
  expect_invalid([&] { assign(taguchi_l9(), {a, a}, {0, 1}); }, "used twice");
  expect_invalid([&] { assign(taguchi_l9(), {Factor{"", {1, 2, 3}}}, {0}); }, "empty");
  expect_invalid([&] { assign(taguchi_l9(), {Factor{"N", {1, kNaN, 3}}}, {0}); }, "non-finite");
}

TEST(FullFactorial, CountsAndUniqueRunsLastFactorFastest) {
  const std::vector<Factor> factors{
      Factor{"A", {0.0, 1.0}}, Factor{"B", {10.0, 20.0, 30.0}}, Factor{"C", {-1, -2, -3, -4}}};
  const Design d = full_factorial(factors);
  ASSERT_EQ(d.runs(), 24);
  std::string why;
  EXPECT_TRUE(d.is_valid(&why)) << why;
  std::set<std::vector<double>> values(d.values.begin(), d.values.end());
  std::set<std::vector<int>> levels(d.level_indices.begin(), d.level_indices.end());
  EXPECT_EQ(values.size(), 24u);
  EXPECT_EQ(levels.size(), 24u);
  EXPECT_EQ(d.level_indices[0], (std::vector<int>{0, 0, 0}));
  EXPECT_EQ(d.level_indices[1], (std::vector<int>{0, 0, 1}));
  EXPECT_EQ(d.level_indices[4], (std::vector<int>{0, 1, 0}));
  EXPECT_EQ(d.level_indices[23], (std::vector<int>{1, 2, 3}));
  EXPECT_EQ(d.values[23], (std::vector<double>{1.0, 30.0, -4.0}));
  // A full factorial is a valid input for the main-effects ANOVA (it is orthogonal).
  std::vector<double> y(24, 1.0);
  EXPECT_NO_THROW(anova(d, y));
}

TEST(FullFactorial, RejectsBadFactors) {
  expect_invalid([] { full_factorial({}); }, "no factors");
  expect_invalid([] { full_factorial({Factor{"A", {}}}); }, "'A'");
  expect_invalid([] { full_factorial({Factor{"A", {1}}, Factor{"A", {2}}}); }, "used twice");
  const Factor big{"big", std::vector<double>(1000, 0.0)};
  expect_invalid(
      [&] {
        full_factorial({big, big, Factor{"c", std::vector<double>(11, 0.0)}});
      },
      "more than");
}

TEST(LatinHypercube, EachStratumHoldsExactlyOnePoint) {
  SCOPED_TRACE(test::seed_message());
  const std::vector<std::string> names{"PV", "PD", "AV"};
  const std::vector<double> lo{0.040, 0.040, 0.008};
  const std::vector<double> hi{0.100, 0.080, 0.016};
  const int cases = test::soak_count(20);
  for (int k = 0; k < cases; ++k) {
    const std::uint64_t seed = test::seed() + static_cast<std::uint64_t>(k);
    const int n = 1 + static_cast<int>(seed % 50);
    const Design d = latin_hypercube(names, lo, hi, n, seed);
    ASSERT_EQ(d.runs(), n);
    EXPECT_FALSE(d.has_levels);
    std::string why;
    EXPECT_TRUE(d.is_valid(&why)) << why;
    for (int f = 0; f < 3; ++f) {
      const auto fs = static_cast<std::size_t>(f);
      std::vector<int> hits(static_cast<std::size_t>(n), 0);
      for (int r = 0; r < n; ++r) {
        const double x = d.value(r, f);
        ASSERT_GE(x, lo[fs]);
        ASSERT_LE(x, hi[fs]);
        const double t = (x - lo[fs]) / (hi[fs] - lo[fs]) * n;
        const int stratum = std::min(n - 1, static_cast<int>(std::floor(t)));
        ++hits[static_cast<std::size_t>(stratum)];
      }
      for (int s = 0; s < n; ++s) {
        EXPECT_EQ(hits[static_cast<std::size_t>(s)], 1)
            << "factor " << f << " stratum " << s << " n " << n << " seed " << seed;
      }
    }
  }
}

TEST(LatinHypercube, DeterministicForASeedAndDifferentForAnother) {
  SCOPED_TRACE(test::seed_message());
  const std::vector<std::string> names{"a", "b"};
  const Design d1 = latin_hypercube(names, {0, -1}, {1, 1}, 30, test::seed());
  const Design d2 = latin_hypercube(names, {0, -1}, {1, 1}, 30, test::seed());
  const Design d3 = latin_hypercube(names, {0, -1}, {1, 1}, 30, test::seed() + 1);
  EXPECT_EQ(d1.values, d2.values);
  EXPECT_NE(d1.values, d3.values);
}

// Seed 42, 4 samples: the values follow from the documented draw order on raw
// std::mt19937_64 output (a sequence the standard fixes), so they must be the same with every
// standard library. Cross-checked with an independent Python implementation of mt19937_64 and
// the documented algorithm. A change here means the draw order changed.
TEST(LatinHypercube, GoldenValuesForSeed42) {
  const Design d = latin_hypercube({"a", "b"}, {0.0, 10.0}, {1.0, 20.0}, 4, 42);
  ASSERT_EQ(d.runs(), 4);
  const double expected[4][2] = {{0.28406817090810926, 17.530956927830037},
                                 {0.22581724160709457, 16.309263972435851},
                                 {0.77351707794070923, 14.213178216806247},
                                 {0.64364257602706598, 11.593345355996782}};
  for (int r = 0; r < 4; ++r) {
    for (int f = 0; f < 2; ++f) EXPECT_DOUBLE_EQ(d.value(r, f), expected[r][f]);
  }
}

TEST(LatinHypercube, StandardEngineSequenceIsTheSpecifiedOne) {
  // C++ standard [rand.predef]: the 10000th output of a default-constructed mt19937_64.
  std::mt19937_64 rng;
  rng.discard(9999);
  EXPECT_EQ(rng(), 9981545732273789042ull);
}

TEST(LatinHypercube, RejectsBadArguments) {
  expect_invalid([] { latin_hypercube({}, {}, {}, 3, 1); }, "no factors");
  expect_invalid([] { latin_hypercube({"a"}, {0, 1}, {1}, 3, 1); }, "size");
  expect_invalid([] { latin_hypercube({"a"}, {0}, {1}, 0, 1); }, "samples");
  expect_invalid([] { latin_hypercube({"a"}, {2}, {1}, 3, 1); }, "'a'");
  expect_invalid([] { latin_hypercube({"a"}, {0}, {kInf}, 3, 1); }, "'a'");
  expect_invalid([] { latin_hypercube({"a", "a"}, {0, 0}, {1, 1}, 3, 1); }, "used twice");
}

TEST(Replicate, RepeatsEachRunConsecutivelyAndAveragesBack) {
  SCOPED_TRACE(test::seed_message());
  const Design base = paper_l18_design();
  const Design rep = replicate(base, 3);
  ASSERT_EQ(rep.runs(), 54);
  std::string why;
  EXPECT_TRUE(rep.is_valid(&why)) << why;
  std::mt19937_64 rng(test::seed());
  std::vector<double> y;
  std::vector<double> expected_means;
  for (int r = 0; r < 54; ++r) {
    const auto rs = static_cast<std::size_t>(r);
    EXPECT_EQ(rep.run_index[rs], r / 3);
    EXPECT_EQ(rep.values[rs], base.values[static_cast<std::size_t>(r / 3)]);
    EXPECT_EQ(rep.level_indices[rs], base.level_indices[static_cast<std::size_t>(r / 3)]);
    y.push_back(static_cast<double>(rng() % 1000) / 8.0);  // exact in binary
    if (r % 3 == 2) expected_means.push_back((y[rs - 2] + y[rs - 1] + y[rs]) / 3.0);
  }
  const ReplicateAverage avg = average_replicates(rep, y);
  EXPECT_EQ(avg.design.values, base.values);
  EXPECT_EQ(avg.design.level_indices, base.level_indices);
  EXPECT_EQ(avg.design.level_counts, base.level_counts);
  EXPECT_EQ(avg.design.run_index, base.run_index);
  EXPECT_EQ(avg.design.factor_names, base.factor_names);
  EXPECT_EQ(avg.repeats, std::vector<int>(18, 3));
  ASSERT_EQ(avg.means.size(), 18u);
  for (std::size_t k = 0; k < 18; ++k) EXPECT_DOUBLE_EQ(avg.means[k], expected_means[k]);
}

TEST(Replicate, NestedReplicationStillMapsToBaseRuns) {
  const Design base = assign(taguchi_l9(), {Factor{"A", {1, 2, 3}}}, {0});
  const Design rep = replicate(replicate(base, 2), 3);
  ASSERT_EQ(rep.runs(), 54);
  const ReplicateAverage avg = average_replicates(rep, std::vector<double>(54, 2.5));
  EXPECT_EQ(avg.design.values, base.values);
  EXPECT_EQ(avg.repeats, std::vector<int>(9, 6));
  EXPECT_EQ(avg.means, std::vector<double>(9, 2.5));
}

TEST(Replicate, RejectsBadInput) {
  const Design base = paper_l18_design();
  expect_invalid([&] { replicate(base, 0); }, "repeats");
  expect_invalid([&] { replicate(Design{}, 2); }, "no factors");
  expect_invalid([&] { average_replicates(base, std::vector<double>(17, 0.0)); }, "responses");
  Design clash = replicate(base, 2);
  clash.values[1][0] += 1.0;  // a "repeat" with a different setting
  expect_invalid([&] { average_replicates(clash, std::vector<double>(36, 0.0)); }, "differ");
}

TEST(Design, IsValidExplainsProblems) {
  Design d = paper_l18_design();
  std::string why;
  ASSERT_TRUE(d.is_valid(&why));
  Design bad = d;
  bad.values[3].pop_back();
  EXPECT_FALSE(bad.is_valid(&why));
  EXPECT_NE(why.find("run 3"), std::string::npos) << why;
  bad = d;
  bad.level_indices[2][1] = 3;
  EXPECT_FALSE(bad.is_valid(&why));
  EXPECT_NE(why.find("'PD'"), std::string::npos) << why;
  bad = d;
  bad.run_index.pop_back();
  EXPECT_FALSE(bad.is_valid(nullptr));
  bad = d;
  bad.factor_names[1] = "PV";
  EXPECT_FALSE(bad.is_valid(&why));
  EXPECT_NE(why.find("twice"), std::string::npos) << why;
  bad = d;
  bad.has_levels = false;
  EXPECT_FALSE(bad.is_valid(nullptr));
  EXPECT_THROW(bad.level(0, 0), std::logic_error);
  EXPECT_THROW(d.value(18, 0), std::out_of_range);
  EXPECT_THROW(d.factor_index("XX"), cmmcomp::ConfigError);
}

}  // namespace
}  // namespace cmmcomp::doe
