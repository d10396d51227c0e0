// SPDX-License-Identifier: MIT
/// @file Gaussian memberships, the shifted (max-normalised) memberships, input normalisation.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/membership.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstddef>
#include <limits>

namespace cmmcomp::fuzzy {
namespace {

TEST(Membership, GaussianMatchesDefinition) {
  for (const double x : {-1.0, 0.0, 0.3, 0.5, 1.7}) {
    const double expected = std::exp(-(x - 0.5) * (x - 0.5) / 0.04);
    EXPECT_NEAR(gaussian_membership(x, 0.5, 0.2), expected, 1e-13 * expected);
  }
  EXPECT_EQ(gaussian_membership(0.5, 0.5, 0.2), 1.0);
  EXPECT_FLOAT_EQ(gaussian_membership(0.3f, 0.5f, 0.2f), std::exp(-1.0f));
}

TEST(Membership, ExponentIsFiniteForAnyInputAndPositiveWidth) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  for (const double x : {1e300, -1e300, kInf, -kInf}) {
    for (const double w : {1e-300, 1e-8, 1.0}) {
      EXPECT_TRUE(std::isfinite(gaussian_exponent(x, 0.5, w)));
      EXPECT_EQ(gaussian_membership(x, 0.5, w), 0.0);
    }
  }
  EXPECT_TRUE(std::isfinite(gaussian_exponent(1e30f, 0.5f, 1e-20f)));
  EXPECT_EQ(gaussian_exponent(1e300, 0.0, 1.0), -kMaxNormalisedDistance * kMaxNormalisedDistance);
}

// The evaluator's shifted memberships, on a one-input network: params = centres, widths, then
// the consequents (unused here).
template <typename Scalar>
std::array<Scalar, 3> shifted(Scalar x,
                              const std::array<Scalar, 3>& c,
                              const std::array<Scalar, 3>& w) {
  using Eval = TskEvaluator<Scalar, 1, 3, 1>;
  std::array<Scalar, Eval::kParamCount> p{};
  for (int s = 0; s < 3; ++s) {
    p[static_cast<std::size_t>(Eval::Layout::centre_index(0, s))] = c[static_cast<std::size_t>(s)];
    p[static_cast<std::size_t>(Eval::Layout::width_index(0, s))] = w[static_cast<std::size_t>(s)];
  }
  typename Eval::Memberships mu{};
  const Scalar total = Eval::memberships(p.data(), {x}, mu);
  EXPECT_EQ(total, mu[0][0] + mu[0][1] + mu[0][2]);
  return mu[0];
}

TEST(Membership, ShiftedMembershipsAreRatiosToTheBestSet) {
  const std::array<double, 3> c{0.0, 0.5, 1.0};
  const std::array<double, 3> w{0.3, 0.2, 0.4};
  for (const double x : {-0.2, 0.1, 0.5, 0.8, 1.3}) {
    const std::array<double, 3> out = shifted(x, c, w);
    double best = 0.0;
    for (int s = 0; s < 3; ++s) best = std::max(best, gaussian_membership(x, c[s], w[s]));
    double top = 0.0;
    for (int s = 0; s < 3; ++s) {
      EXPECT_NEAR(out[s], gaussian_membership(x, c[s], w[s]) / best, 1e-15) << "x=" << x;
      top = std::max(top, out[s]);
    }
    EXPECT_EQ(top, 1.0);
  }
}

TEST(Membership, ShiftedMembershipsSurviveTotalUnderflow) {
  // At x = 1e6 every plain membership is exp(-1e13) = 0; the shifted ones keep the nearest set.
  const std::array<double, 3> c{0.0, 0.5, 1.0};
  const std::array<double, 3> w{0.3, 0.3, 0.3};
  const std::array<double, 3> out = shifted(1e6, c, w);
  EXPECT_EQ(gaussian_membership(1e6, 1.0, 0.3), 0.0);
  EXPECT_EQ(out[2], 1.0);
  EXPECT_EQ(out[1], 0.0);
  EXPECT_EQ(out[0], 0.0);
  const std::array<float, 3> outf = shifted(
      -1e30f, std::array<float, 3>{0.0f, 0.5f, 1.0f}, std::array<float, 3>{0.3f, 0.3f, 0.3f});
  for (const float v : outf) EXPECT_TRUE(std::isfinite(v));
  EXPECT_EQ(outf[0], 1.0f);
}

TEST(Membership, NormaliseMapsTheRangeOntoUnitInterval) {
  const InputRange r{0.01, 0.05};
  EXPECT_EQ(normalise(0.01, r), 0.0);
  EXPECT_EQ(normalise(0.05, r), 1.0);
  EXPECT_NEAR(normalise(0.03, r), 0.5, 1e-15);
  EXPECT_NEAR(normalise(0.09, r), 2.0, 1e-15);  // linear beyond the range
  static_assert(normalise(3.0, InputRange{1.0, 5.0}) == 0.5);
}

TEST(Membership, MinMaxClampHelpers) {
  static_assert(detail::max_of(1.0, 2.0) == 2.0);
  static_assert(detail::min_of(1.0, 2.0) == 1.0);
  static_assert(detail::clamp_of(3.0, 0.0, 1.0) == 1.0);
  static_assert(detail::clamp_of(-3.0, 0.0, 1.0) == 0.0);
  static_assert(detail::clamp_of(0.25, 0.0, 1.0) == 0.25);
  SUCCEED();
}

}  // namespace
}  // namespace cmmcomp::fuzzy
