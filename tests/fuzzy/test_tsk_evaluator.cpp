// SPDX-License-Identifier: MIT
/// @file T-S evaluator: against a naive reference, multi-output, domain policies, NaN safety,
/// validate().
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "support/test_seed.hpp"

namespace cmmcomp::fuzzy {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

// A random valid model: ranges of a few units, centres spread over [0, 1], widths 0.2..0.6,
// consequents in [-1, 1].
template <typename Scalar, int kIn, int kSets, int kOut>
TskModel<Scalar, kIn, kSets, kOut> random_model(std::mt19937_64& rng) {
  TskModel<Scalar, kIn, kSets, kOut> m;
  std::uniform_real_distribution<double> lo(-5.0, 5.0);
  std::uniform_real_distribution<double> span(0.1, 10.0);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> width(0.2, 0.6);
  std::uniform_real_distribution<double> coef(-1.0, 1.0);
  for (auto& r : m.ranges) {
    r.lo = lo(rng);
    r.hi = r.lo + span(rng);
  }
  for (int i = 0; i < kIn; ++i) {
    for (int s = 0; s < kSets; ++s) {
      m.params.centre(i, s) = static_cast<Scalar>(unit(rng));
      m.params.width(i, s) = static_cast<Scalar>(width(rng));
    }
  }
  for (int o = 0; o < kOut; ++o) {
    for (int j = 0; j < m.kRules; ++j) {
      for (int k = 0; k <= kIn; ++k) m.params.consequent(o, j, k) = static_cast<Scalar>(coef(rng));
    }
  }
  return m;
}

template <typename Model>
typename Model::RawInput random_inside(const Model& m, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  typename Model::RawInput x{};
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = m.ranges[i].lo + unit(rng) * (m.ranges[i].hi - m.ranges[i].lo);
  }
  return x;
}

// The deliberately naive reference, in double: for every rule, the explicit product of the
// plain memberships exp(-(x-c)^2/sigma^2), then the weighted mean of the rule outputs.
// `scale` receives sum_j abar_j |y_j|, the size of the terms (for a relative tolerance).
template <typename Scalar, int kIn, int kSets, int kOut>
std::array<double, kOut> reference(const TskModel<Scalar, kIn, kSets, kOut>& m,
                                   const typename TskModel<Scalar, kIn, kSets, kOut>::RawInput& raw,
                                   typename TskModel<Scalar, kIn, kSets, kOut>::RawOutput& scale) {
  using Layout = TskLayout<kIn, kSets, kOut>;
  std::array<double, kIn> x{};
  for (int i = 0; i < kIn; ++i) {
    const InputRange& r = m.ranges[static_cast<unsigned>(i)];
    x[static_cast<unsigned>(i)] = (raw[static_cast<unsigned>(i)] - r.lo) / (r.hi - r.lo);
  }
  std::array<double, kOut> num{};
  scale = {};
  double den = 0.0;
  for (int j = 0; j < Layout::kRules; ++j) {
    double alpha = 1.0;
    for (int i = 0; i < kIn; ++i) {
      const int s = Layout::rule_set(j, i);
      const double c = static_cast<double>(m.params.centre(i, s));
      const double w = static_cast<double>(m.params.width(i, s));
      const double d = x[static_cast<unsigned>(i)] - c;
      alpha *= std::exp(-(d * d) / (w * w));
    }
    den += alpha;
    for (int o = 0; o < kOut; ++o) {
      double yj = static_cast<double>(m.params.consequent(o, j, 0));
      for (int i = 0; i < kIn; ++i) {
        yj += static_cast<double>(m.params.consequent(o, j, i + 1)) * x[static_cast<unsigned>(i)];
      }
      num[static_cast<unsigned>(o)] += alpha * yj;
      scale[static_cast<unsigned>(o)] += alpha * std::fabs(yj);
    }
  }
  for (int o = 0; o < kOut; ++o) {
    num[static_cast<unsigned>(o)] /= den;
    scale[static_cast<unsigned>(o)] /= den;
  }
  return num;
}

// Evaluator vs reference on `cases` random models and inputs; |y - y_ref| <= tol * scale.
template <typename Scalar, int kIn, int kSets, int kOut>
void expect_matches_reference(double tol, int cases) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed());
  double worst = 0.0;
  for (int c = 0; c < cases; ++c) {
    const auto m = random_model<Scalar, kIn, kSets, kOut>(rng);
    for (int k = 0; k < 20; ++k) {
      const auto x = random_inside(m, rng);
      std::array<double, kOut> y{};
      ASSERT_EQ(evaluate(m, x, y, DomainPolicy::kReject), Status::kOk);
      std::array<double, kOut> scale{};
      const auto ref = reference(m, x, scale);
      for (std::size_t o = 0; o < y.size(); ++o) {
        const double err = std::fabs(y[o] - ref[o]) / (scale[o] + 1e-300);
        worst = std::max(worst, err);
        ASSERT_LE(err, tol) << "case " << c << " sample " << k << " output " << o;
      }
    }
  }
  ::testing::Test::RecordProperty("worst_relative_error", std::to_string(worst));
}

TEST(TskEvaluator, PaperNetworkMatchesNaiveReferenceDouble) {
  expect_matches_reference<double, 4, 3, 1>(1e-12, test::soak_count(200));
}

TEST(TskEvaluator, MultiOutputNetworkMatchesNaiveReferenceDouble) {
  expect_matches_reference<double, 4, 3, 4>(1e-12, test::soak_count(200));
}

TEST(TskEvaluator, OtherShapesMatchNaiveReferenceDouble) {
  expect_matches_reference<double, 1, 1, 1>(1e-12, 50);
  expect_matches_reference<double, 1, 5, 2>(1e-12, 50);
  expect_matches_reference<double, 2, 2, 3>(1e-12, 50);
  expect_matches_reference<double, 3, 4, 1>(1e-12, 50);
  expect_matches_reference<double, 5, 2, 2>(1e-12, 50);
  expect_matches_reference<double, 5, 3, 4>(1e-12, 10);  // the 5-input compensation model
}

TEST(TskEvaluator, FloatMatchesNaiveReference) {
  expect_matches_reference<float, 4, 3, 4>(1e-4, test::soak_count(200));
  expect_matches_reference<float, 2, 3, 1>(1e-4, 50);
  expect_matches_reference<float, 4, 3, 1>(1e-4, 50);
}

// The two loop nests of the consequent sums (SumRoute) perform the same operations in the same
// order: the firmware's chunked route gives the host's bits (tests/data/golden checks it on the
// Cortex-M7; this checks it on every build, for shapes the golden vectors do not cover).
template <typename Scalar, int kIn, int kSets, int kOut>
void expect_routes_agree_bitwise(int cases) {
  using Model = TskModel<Scalar, kIn, kSets, kOut>;
  using Evaluator = typename Model::Evaluator;
  std::mt19937_64 rng(test::seed() + 3);
  std::uniform_real_distribution<double> unit(-0.5, 1.5);
  for (int c = 0; c < cases; ++c) {
    const Model m = random_model<Scalar, kIn, kSets, kOut>(rng);
    typename Evaluator::Input x;
    for (auto& v : x) v = static_cast<Scalar>(unit(rng));
    typename Evaluator::Output by_rule;
    typename Evaluator::Output chunked;
    Evaluator::template forward<SumRoute::kByRule>(m.params.data(), x, by_rule);
    Evaluator::template forward<SumRoute::kChunked>(m.params.data(), x, chunked);
    for (int o = 0; o < kOut; ++o) {
      const auto k = static_cast<unsigned>(o);
      ASSERT_EQ(std::memcmp(&by_rule[k], &chunked[k], sizeof(Scalar)), 0)
          << "case " << c << " output " << o << ": " << by_rule[k] << " vs " << chunked[k];
    }
  }
}

TEST(TskEvaluator, SumRoutesGiveTheSameBits) {
  expect_routes_agree_bitwise<double, 4, 3, 4>(300);
  expect_routes_agree_bitwise<float, 4, 3, 4>(300);
  expect_routes_agree_bitwise<double, 5, 3, 4>(100);
  expect_routes_agree_bitwise<float, 5, 3, 4>(100);
  expect_routes_agree_bitwise<double, 3, 3, 4>(100);  // 27 rules: an odd count
  expect_routes_agree_bitwise<double, 3, 2, 8>(100);  // a block of 32
}

TEST(TskEvaluator, MultiOutputEqualsSeparateSingleOutputNetworks) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 1);
  for (int c = 0; c < 100; ++c) {
    const auto multi = random_model<double, 4, 3, 4>(rng);
    std::array<PaperNetwork, 4> single;
    for (int o = 0; o < 4; ++o) {
      PaperNetwork& s = single[static_cast<unsigned>(o)];
      s.ranges = multi.ranges;
      for (int i = 0; i < 4; ++i) {
        for (int k = 0; k < 3; ++k) {
          s.params.centre(i, k) = multi.params.centre(i, k);
          s.params.width(i, k) = multi.params.width(i, k);
        }
      }
      for (int j = 0; j < PaperNetwork::kRules; ++j) {
        for (int t = 0; t < 5; ++t) s.params.consequent(0, j, t) = multi.params.consequent(o, j, t);
      }
    }
    const auto x = random_inside(multi, rng);
    std::array<double, 4> y{};
    ASSERT_EQ(evaluate(multi, x, y, DomainPolicy::kClamp), Status::kOk);
    for (int o = 0; o < 4; ++o) {
      std::array<double, 1> y1{};
      ASSERT_EQ(evaluate(single[static_cast<unsigned>(o)], x, y1, DomainPolicy::kClamp),
                Status::kOk);
      // The two take different kernels (one rule's block: 20 values vs 5, tsk_evaluator.hpp),
      // so they agree to round-off relative to the size of the terms.
      std::array<double, 1> scale{};
      reference(single[static_cast<unsigned>(o)], x, scale);
      EXPECT_NEAR(y1[0], y[static_cast<unsigned>(o)], 1e-13 * scale[0]) << "output " << o;
    }
  }
}

TEST(TskEvaluator, FiringStrengthsFollowRuleNumberingAndSumToTotal) {
  std::mt19937_64 rng(test::seed() + 2);
  const auto m = random_model<double, 4, 3, 1>(rng);
  using Eval = PaperNetwork::Evaluator;
  const Eval::Input x{0.1, 0.45, 0.8, 0.3};
  Eval::Firing alpha{};
  const double total = Eval::firing(m.params.data(), x, alpha);
  Eval::Memberships mu{};
  EXPECT_DOUBLE_EQ(Eval::memberships(m.params.data(), x, mu), total);
  double sum = 0.0;
  double best = 0.0;
  for (int j = 0; j < Eval::kRules; ++j) {
    double product = 1.0;
    for (int i = 0; i < 4; ++i) {
      product *=
          mu[static_cast<unsigned>(i)][static_cast<unsigned>(PaperNetwork::Params::rule_set(j, i))];
    }
    EXPECT_NEAR(alpha[static_cast<unsigned>(j)], product, 1e-15) << "rule " << j;
    sum += alpha[static_cast<unsigned>(j)];
    best = std::max(best, alpha[static_cast<unsigned>(j)]);
  }
  EXPECT_NEAR(sum, total, 1e-13 * total);
  EXPECT_EQ(best, 1.0);  // the shift makes the best rule fire with exactly 1
  EXPECT_GE(total, 1.0);
}

// A fixed 2-input model with ranges [0, 10] and [-1, 1].
TskModel<double, 2, 2, 2> small_model() {
  std::mt19937_64 rng(7);
  auto m = random_model<double, 2, 2, 2>(rng);
  m.ranges = {InputRange{0.0, 10.0}, InputRange{-1.0, 1.0}};
  return m;
}

TEST(TskEvaluator, InsideDomainIsOkAndClearsMask) {
  const auto m = small_model();
  std::array<double, 2> y{};
  std::uint32_t mask = 0xffu;
  EXPECT_EQ(evaluate(m, {0.0, 1.0}, y, DomainPolicy::kReject, &mask), Status::kOk);  // bounds
  EXPECT_EQ(mask, 0u);
  EXPECT_EQ(evaluate(m, {10.0, -1.0}, y, DomainPolicy::kReject, &mask), Status::kOk);
  EXPECT_EQ(mask, 0u);
}

TEST(TskEvaluator, ClampPolicyEvaluatesAtTheBoundaryAndFlags) {
  const auto m = small_model();
  std::array<double, 2> y{};
  std::array<double, 2> y_edge{};
  std::uint32_t mask = 0;
  EXPECT_EQ(evaluate(m, {12.0, 0.5}, y, DomainPolicy::kClamp, &mask), Status::kOutsideDomain);
  EXPECT_EQ(mask, 0b01u);
  EXPECT_EQ(evaluate(m, {10.0, 0.5}, y_edge, DomainPolicy::kClamp), Status::kOk);
  EXPECT_EQ(y, y_edge);
  EXPECT_EQ(evaluate(m, {-3.0, -7.0}, y, DomainPolicy::kClamp, &mask), Status::kOutsideDomain);
  EXPECT_EQ(mask, 0b11u);
  EXPECT_EQ(evaluate(m, {0.0, -1.0}, y_edge, DomainPolicy::kClamp), Status::kOk);
  EXPECT_EQ(y, y_edge);
  EXPECT_EQ(evaluate(m, {5.0, 1.5}, y, DomainPolicy::kClamp, &mask), Status::kOutsideDomain);
  EXPECT_EQ(mask, 0b10u);
}

TEST(TskEvaluator, ExtrapolatePolicyEvaluatesAsIsAndFlags) {
  const auto m = small_model();
  std::array<double, 2> y{};
  std::uint32_t mask = 0;
  EXPECT_EQ(evaluate(m, {12.0, 0.5}, y, DomainPolicy::kExtrapolate, &mask), Status::kOutsideDomain);
  EXPECT_EQ(mask, 0b01u);
  std::array<double, 2> scale{};
  const auto ref = reference(m, {12.0, 0.5}, scale);
  for (std::size_t o = 0; o < 2; ++o) EXPECT_NEAR(y[o], ref[o], 1e-12 * scale[o]);
  std::array<double, 2> y_clamped{};
  EXPECT_EQ(evaluate(m, {12.0, 0.5}, y_clamped, DomainPolicy::kClamp), Status::kOutsideDomain);
  EXPECT_NE(y, y_clamped);
}

TEST(TskEvaluator, RejectPolicyLeavesOutputUntouched) {
  const auto m = small_model();
  std::array<double, 2> y{42.0, 43.0};
  std::uint32_t mask = 0;
  EXPECT_EQ(evaluate(m, {5.0, 1.0000001}, y, DomainPolicy::kReject, &mask),
            Status::kOutsideDomainRejected);
  EXPECT_EQ(mask, 0b10u);
  EXPECT_EQ(y[0], 42.0);
  EXPECT_EQ(y[1], 43.0);
  EXPECT_FALSE(ok(Status::kOutsideDomainRejected));
  EXPECT_STREQ(to_string(Status::kOutsideDomainRejected),
               "outside the training domain (rejected by policy)");
}

TEST(TskEvaluator, NonFiniteInputIsInvalidAndLeavesOutputUntouched) {
  const auto m = small_model();
  for (const double bad : {kNaN, kInf, -kInf}) {
    for (const DomainPolicy policy :
         {DomainPolicy::kClamp, DomainPolicy::kExtrapolate, DomainPolicy::kReject}) {
      std::array<double, 2> y{42.0, 43.0};
      std::uint32_t mask = 0xdeadu;
      EXPECT_EQ(evaluate(m, {bad, 0.0}, y, policy, &mask), Status::kInvalidInput);
      EXPECT_EQ(evaluate(m, {1.0, bad}, y, policy, &mask), Status::kInvalidInput);
      EXPECT_EQ(y[0], 42.0);
      EXPECT_EQ(y[1], 43.0);
      EXPECT_EQ(mask, 0xdeadu);  // not written for a non-finite input
    }
  }
}

TEST(TskEvaluator, UnknownPolicyIsInvalid) {
  const auto m = small_model();
  std::array<double, 2> y{42.0, 43.0};
  EXPECT_EQ(evaluate(m, {1.0, 0.0}, y, static_cast<DomainPolicy>(7)), Status::kInvalidInput);
  EXPECT_EQ(y[0], 42.0);
}

TEST(TskEvaluator, ExtremeInputsNeverProduceNaN) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 3);
  const double extremes[] = {1e300, -1e300, 1.7e308, -1.7e308, 1e30, -1e30, 1e8, -1e8};
  int computed = 0;
  for (int c = 0; c < 20; ++c) {
    const auto m = random_model<double, 4, 3, 4>(rng);
    const auto mf = random_model<float, 4, 3, 4>(rng);
    for (const double e : extremes) {
      for (int i = 0; i < 4; ++i) {
        auto x = random_inside(m, rng);
        x[static_cast<unsigned>(i)] = e;
        for (const DomainPolicy policy : {DomainPolicy::kClamp, DomainPolicy::kExtrapolate}) {
          std::array<double, 4> y{1.0, 2.0, 3.0, 4.0};
          const Status s = evaluate(m, x, y, policy);
          std::array<double, 4> yf{1.0, 2.0, 3.0, 4.0};
          const Status sf = evaluate(mf, x, yf, policy);
          for (std::size_t o = 0; o < 4; ++o) {
            ASSERT_TRUE(std::isfinite(y[o])) << "input " << i << " = " << e;
            ASSERT_TRUE(std::isfinite(yf[o])) << "float, input " << i << " = " << e;
          }
          // Clamping always computes; extrapolating may give up (kInvalidInput) on overflow.
          if (policy == DomainPolicy::kClamp) {
            ASSERT_EQ(s, Status::kOutsideDomain);
            ASSERT_EQ(sf, Status::kOutsideDomain);
          } else {
            ASSERT_TRUE(s == Status::kOutsideDomain || s == Status::kInvalidInput);
            ASSERT_TRUE(sf == Status::kOutsideDomain || sf == Status::kInvalidInput);
            computed += s == Status::kOutsideDomain ? 1 : 0;
          }
        }
      }
    }
  }
  EXPECT_GT(computed, 0);  // moderate extrapolation (1e8) is computed, not refused
}

TEST(TskEvaluator, FarExtrapolationFollowsTheOutermostSet) {
  // Far beyond the range, the nearest (outermost) set dominates although every plain
  // membership underflows to 0: the result is that set's rules, not 0/0.
  TskModel<double, 1, 2, 1> m;
  m.ranges = {InputRange{0.0, 1.0}};
  m.params.centre(0, 0) = 0.0;
  m.params.centre(0, 1) = 1.0;
  m.params.width(0, 0) = 0.3;
  m.params.width(0, 1) = 0.3;
  m.params.consequent(0, 0, 0) = -1.0;  // rule 0 (set 0): y = -1
  m.params.consequent(0, 1, 0) = 2.0;   // rule 1 (set 1): y = 2 + 0.5 x
  m.params.consequent(0, 1, 1) = 0.5;
  std::array<double, 1> y{};
  EXPECT_EQ(evaluate(m, {100.0}, y, DomainPolicy::kExtrapolate), Status::kOutsideDomain);
  EXPECT_DOUBLE_EQ(y[0], 2.0 + 0.5 * 100.0);
  EXPECT_EQ(evaluate(m, {-100.0}, y, DomainPolicy::kExtrapolate), Status::kOutsideDomain);
  EXPECT_DOUBLE_EQ(y[0], -1.0);
}

TEST(TskEvaluator, OverflowingResultIsInvalidAndLeavesOutputUntouched) {
  TskModel<double, 1, 2, 1> m;
  m.ranges = {InputRange{0.0, 1.0}};
  m.params.centre(0, 1) = 1.0;
  m.params.width(0, 0) = 0.5;
  m.params.width(0, 1) = 0.5;
  m.params.consequent(0, 0, 0) = 1e308;
  m.params.consequent(0, 1, 0) = 1e308;
  ASSERT_TRUE(validate(m));
  std::array<double, 1> y{42.0};
  EXPECT_EQ(evaluate(m, {0.5}, y, DomainPolicy::kClamp), Status::kInvalidInput);
  EXPECT_EQ(y[0], 42.0);
  m.params.consequent(0, 0, 0) = 1.0;
  m.params.consequent(0, 1, 0) = 1.0;
  m.params.consequent(0, 1, 1) = 1e300;
  EXPECT_EQ(evaluate(m, {1e300}, y, DomainPolicy::kExtrapolate), Status::kInvalidInput);
  EXPECT_EQ(y[0], 42.0);
}

TEST(TskEvaluator, ValidateAcceptsRandomModels) {
  std::mt19937_64 rng(test::seed() + 4);
  std::string why = "unchanged";
  EXPECT_TRUE(validate(random_model<double, 4, 3, 4>(rng), &why));
  EXPECT_TRUE(validate(random_model<float, 4, 3, 1>(rng), &why));
  EXPECT_EQ(why, "unchanged");
  EXPECT_TRUE(validate(random_model<double, 2, 2, 2>(rng)));  // why is optional
}

TEST(TskEvaluator, ValidateRejectsBadModels) {
  std::mt19937_64 rng(test::seed() + 5);
  const auto good = random_model<double, 4, 3, 1>(rng);
  std::string why;
  auto m = good;
  m.params.width(2, 1) = 0.0;
  EXPECT_FALSE(validate(m, &why));
  EXPECT_EQ(why, "width of set 1 of input 2 is not positive");
  m = good;
  m.params.width(0, 0) = -0.3;
  EXPECT_FALSE(validate(m, &why));
  m = good;
  m.params.consequent(0, 80, 4) = kNaN;
  EXPECT_FALSE(validate(m, &why));
  EXPECT_EQ(why,
            "parameter " + std::to_string(PaperNetwork::Params::consequent_index(0, 80, 4)) +
                " is not finite");
  m = good;
  m.params.centre(3, 2) = kInf;
  EXPECT_FALSE(validate(m, &why));
  m = good;
  m.ranges[1] = InputRange{2.0, 2.0};
  EXPECT_FALSE(validate(m, &why));
  EXPECT_EQ(why, "range of input 1 has lo >= hi");
  m.ranges[1] = InputRange{3.0, 2.0};
  EXPECT_FALSE(validate(m));
  m.ranges[1] = InputRange{kNaN, 2.0};
  EXPECT_FALSE(validate(m, &why));
  EXPECT_EQ(why, "range of input 1 is not finite");
  m.ranges[1] = InputRange{-1e308, 1e308};  // hi - lo overflows
  EXPECT_FALSE(validate(m, &why));
}

TEST(DomainPolicyNames, ParseIsTheInverseOfToStringAndRejectsTheRest) {
  for (const DomainPolicy p : kDomainPolicies) {
    DomainPolicy parsed = p == DomainPolicy::kReject ? DomainPolicy::kClamp : DomainPolicy::kReject;
    EXPECT_TRUE(parse_domain_policy(to_string(p), &parsed)) << to_string(p);
    EXPECT_EQ(parsed, p);
  }
  DomainPolicy kept = DomainPolicy::kExtrapolate;
  for (const char* bad : {"", "Clamp", "clamp ", "rejected", "unknown"}) {
    EXPECT_FALSE(parse_domain_policy(bad, &kept)) << bad;
    EXPECT_EQ(kept, DomainPolicy::kExtrapolate) << "a failed parse changed the policy";
  }
  static_assert(to_string(DomainPolicy::kClamp)[0] == 'c', "constexpr");
}

}  // namespace
}  // namespace cmmcomp::fuzzy
