// SPDX-License-Identifier: MIT
/// @file exp_nonpositive against libm: ulp error over the whole accepted range, the ends, and
/// the same bits when the compiler vectorises it.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/exp_nonpositive.hpp>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <type_traits>

namespace cmmcomp::fuzzy {
namespace {

// Distance in units in the last place between two finite positive values of the same type.
template <typename T>
double ulps(T a, T b) {
  using Int = std::conditional_t<sizeof(T) == 8, std::int64_t, std::int32_t>;
  Int ia = 0;
  Int ib = 0;
  std::memcpy(&ia, &a, sizeof a);
  std::memcpy(&ib, &b, sizeof b);
  return static_cast<double>(ia > ib ? ia - ib : ib - ia);  // same sign: no overflow
}

TEST(ExpNonpositive, DoubleWithinTwoUlpOfLibm) {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> wide(-708.0, 0.0);
  std::uniform_real_distribution<double> narrow(-2.0, 0.0);  // the memberships that matter
  double worst = 0;
  for (int k = 0; k < 200000; ++k) {
    const double v = (k % 2 == 0) ? wide(rng) : narrow(rng);
    const double got = exp_nonpositive(v);
    const double want = std::exp(v);
    worst = std::max(worst, ulps(got, want));
    ASSERT_LE(ulps(got, want), 2.0) << "v = " << v;
  }
  // The reduction's boundaries: k·ln2 ± half a step, and exact multiples of ln2.
  for (int k = 0; k <= 1021; ++k) {
    for (const double d : {-0.5, -1e-9, 0.0, 1e-9, 0.5}) {
      const double v = std::min(0.0, (-k + d) * 0.6931471805599453);
      if (v < -708.0) continue;
      ASSERT_LE(ulps(exp_nonpositive(v), std::exp(v)), 2.0) << "v = " << v;
    }
  }
  RecordProperty("worst_ulp", std::to_string(worst));
}

TEST(ExpNonpositive, FloatWithinTwoUlpOfLibm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<float> wide(-87.0f, 0.0f);
  std::uniform_real_distribution<float> narrow(-2.0f, 0.0f);
  for (int k = 0; k < 200000; ++k) {
    const float v = (k % 2 == 0) ? wide(rng) : narrow(rng);
    const float want = static_cast<float>(std::exp(static_cast<double>(v)));  // correctly rounded
    ASSERT_LE(ulps(exp_nonpositive(v), want), 2.0) << "v = " << v;
  }
}

TEST(ExpNonpositive, EndsOfTheRange) {
  EXPECT_EQ(exp_nonpositive(0.0), 1.0);
  EXPECT_EQ(exp_nonpositive(-0.0), 1.0);
  EXPECT_EQ(exp_nonpositive(0.0f), 1.0f);
  EXPECT_GT(exp_nonpositive(-708.0 + 1e-12), std::numeric_limits<double>::min());
  EXPECT_EQ(exp_nonpositive(-708.5), 0.0);
  EXPECT_EQ(exp_nonpositive(-1e36), 0.0);
  EXPECT_EQ(exp_nonpositive(-std::numeric_limits<double>::infinity()), 0.0);
  EXPECT_EQ(exp_nonpositive(-std::numeric_limits<double>::max()), 0.0);
  EXPECT_GT(exp_nonpositive(-86.9f), std::numeric_limits<float>::min());
  EXPECT_EQ(exp_nonpositive(-87.5f), 0.0f);
  EXPECT_EQ(exp_nonpositive(-1e30f), 0.0f);
  EXPECT_EQ(exp_nonpositive(-std::numeric_limits<float>::infinity()), 0.0f);
}

// A loop the compiler vectorises (release builds) gives the same bits as one call at a time,
// kept scalar by the volatile round trip.
TEST(ExpNonpositive, VectorisedLoopGivesTheScalarBits) {
  std::array<double, 64> v{};
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> d(-40.0, 0.0);
  for (double& x : v) x = d(rng);
  std::array<double, 64> loop{};
  for (std::size_t k = 0; k < v.size(); ++k) loop[k] = exp_nonpositive(v[k]);
  for (std::size_t k = 0; k < v.size(); ++k) {
    volatile double x = v[k];
    const double one = exp_nonpositive(static_cast<double>(x));
    EXPECT_EQ(std::memcmp(&one, &loop[k], sizeof one), 0) << "k = " << k;
  }
}

}  // namespace
}  // namespace cmmcomp::fuzzy
