// SPDX-License-Identifier: MIT
/// @file Move profiles: exact distances, continuity, limits, instants, invalid input.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/motion/move_profile.hpp>
#include <limits>
#include <random>

#include "support/test_seed.hpp"

namespace cmmcomp::motion {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

MoveProfile planned(const ProbingMove& m) {
  MoveProfile p;
  EXPECT_EQ(MoveProfile::plan(m, p), Status::kOk);
  return p;
}

// Checks every property a valid profile must have; returns nothing, reports through gtest.
void expect_valid_profile(const MoveProfile& p) {
  const ProbingMove& m = p.move();
  const PhaseInstants& in = p.instants();
  const double dscale = m.positioning_distance + m.approach_distance;
  const double eps_p = 1e-12 * dscale;
  const double eps_v = 1e-9 * std::max(m.positioning_speed, m.approach_speed);
  const double eps_a = 1e-9 * std::max(m.positioning_accel, m.approach_accel);

  ASSERT_GE(p.segment_count(), 2);
  ASSERT_LE(p.segment_count(), MoveProfile::kMaxSegments);
  EXPECT_LE(0.0, in.positioning_accel_end);
  EXPECT_LT(in.positioning_accel_end, in.positioning_end);
  EXPECT_LE(in.positioning_accel_end, in.positioning_decel_start);
  EXPECT_LT(in.positioning_decel_start, in.positioning_end);
  EXPECT_NEAR(in.approach_start - in.positioning_end, m.dwell, 1e-12 * in.touch);
  EXPECT_LT(in.approach_start, in.touch);
  EXPECT_LE(in.approach_start, in.approach_accel_end);
  EXPECT_LE(in.approach_accel_end, in.touch);

  // Segments tile [0, touch] with no gap.
  EXPECT_EQ(p.segment(0).start_time, 0.0);
  for (int i = 1; i < p.segment_count(); ++i) {
    const Segment& a = p.segment(i - 1);
    const Segment& b = p.segment(i);
    EXPECT_NEAR(a.end_time(), b.start_time, 1e-12 * in.touch) << "segment " << i;
    const MotionState ea = a.at(a.duration);
    // Position and velocity are continuous everywhere; acceleration too when jerk-limited.
    EXPECT_NEAR(ea.position, b.p0, eps_p) << "segment " << i;
    EXPECT_NEAR(ea.velocity, b.v0, eps_v) << "segment " << i;
    if (m.jerk > 0.0 || m.smoothing > 0.0) {
      EXPECT_NEAR(ea.acceleration, b.a0, eps_a) << "segment " << i;
    }
  }

  // Exact distances: at rest at PD at the end of positioning, at PD + AD at the touch.
  const MotionState pos_end = p.sample(in.positioning_end);
  EXPECT_NEAR(pos_end.position, m.positioning_distance, eps_p);
  EXPECT_NEAR(pos_end.velocity, 0.0, eps_v);
  const MotionState touch = p.sample(in.touch);
  EXPECT_NEAR(touch.position, m.positioning_distance + m.approach_distance, eps_p);
  EXPECT_GT(touch.velocity, 0.0);

  // Limits respected, velocity never negative, through a dense sweep.
  const int n = 4000;
  for (int k = 0; k <= n; ++k) {
    const double t = in.touch * k / n;
    const MotionState s = p.sample(t);
    const bool positioning = t <= in.positioning_end;
    const double vmax = positioning ? m.positioning_speed : m.approach_speed;
    const double amax = positioning ? m.positioning_accel : m.approach_accel;
    ASSERT_GE(s.velocity, -eps_v) << "t=" << t;
    ASSERT_LE(s.velocity, vmax + eps_v) << "t=" << t;
    ASSERT_LE(std::fabs(s.acceleration), amax + eps_a) << "t=" << t;
    // Smoothing over T limits the jerk to accel / T in each phase.
    double jmax = m.jerk > 0.0 ? m.jerk : std::numeric_limits<double>::infinity();
    if (m.smoothing > 0.0) jmax = std::min(jmax, amax / m.smoothing);
    ASSERT_LE(std::fabs(s.jerk), jmax * (1 + 1e-12)) << "t=" << t;
    if (t > in.positioning_end && t < in.approach_start) {
      ASSERT_NEAR(s.velocity, 0.0, eps_v) << "dwell, t=" << t;
      ASSERT_NEAR(s.position, m.positioning_distance, eps_p) << "dwell, t=" << t;
    }
  }

  // Speed reached or not, as the profile reports.
  if (p.approach_reaches_speed()) {
    EXPECT_NEAR(touch.velocity, m.approach_speed, eps_v);
    EXPECT_NEAR(p.sample(in.approach_accel_end).velocity, m.approach_speed, eps_v);
  } else {
    EXPECT_LT(touch.velocity, m.approach_speed);
    EXPECT_EQ(in.approach_accel_end, in.touch);
  }
  const MotionState peak = p.sample(in.positioning_accel_end);
  EXPECT_NEAR(peak.velocity, p.positioning_peak_speed(), eps_v);
  if (p.positioning_reaches_speed()) {
    EXPECT_NEAR(p.positioning_peak_speed(), m.positioning_speed, eps_v);
  } else {
    EXPECT_LT(p.positioning_peak_speed(), m.positioning_speed);
  }
}

TEST(MoveProfile, BaselineInstantsAreExact) {
  const MoveProfile p = planned(baseline_move());
  // 0.2 s ramp, 0.8 s cruise over 32 mm, 0.2 s ramp; approach: 0.2 s ramp, 8.8 mm at 12 mm/s.
  EXPECT_NEAR(p.instants().positioning_accel_end, 0.2, 1e-15);
  EXPECT_NEAR(p.instants().positioning_decel_start, 1.0, 1e-15);
  EXPECT_NEAR(p.instants().positioning_end, 1.2, 1e-15);
  EXPECT_EQ(p.instants().approach_start, p.instants().positioning_end);  // no dwell
  EXPECT_NEAR(p.instants().approach_accel_end, 1.4, 1e-15);
  EXPECT_NEAR(p.instants().touch, 1.4 + 8.8 / 12.0, 1e-15);
  EXPECT_EQ(p.segment_count(), 5);
  EXPECT_TRUE(p.positioning_reaches_speed());
  EXPECT_TRUE(p.approach_reaches_speed());
  expect_valid_profile(p);
  const MotionState mid = p.sample(0.1);
  EXPECT_NEAR(mid.position, 0.5 * 0.2 * 0.01, 1e-16);
  EXPECT_NEAR(mid.velocity, 0.02, 1e-16);
  EXPECT_EQ(mid.acceleration, 0.2);
}

TEST(MoveProfile, TriangularPositioningWhenDistanceTooShort) {
  ProbingMove m = baseline_move();
  m.positioning_speed = 0.100;  // needs 50 mm of ramps; PD = 40 mm
  const MoveProfile p = planned(m);
  EXPECT_FALSE(p.positioning_reaches_speed());
  EXPECT_NEAR(p.positioning_peak_speed(), std::sqrt(0.040 * 0.200), 1e-15);
  EXPECT_NEAR(p.instants().positioning_accel_end, std::sqrt(0.040 / 0.200), 1e-15);
  EXPECT_NEAR(p.instants().positioning_end, 2.0 * std::sqrt(0.040 / 0.200), 1e-15);
  // No cruise: the deceleration starts at the peak-speed instant.
  EXPECT_EQ(p.instants().positioning_decel_start, p.instants().positioning_accel_end);
  expect_valid_profile(p);
}

TEST(MoveProfile, DwellHoldsThePreHitPointAndShiftsTheApproach) {
  ProbingMove m = baseline_move();
  m.dwell = 0.8;
  const MoveProfile p = planned(m);
  EXPECT_NEAR(p.instants().positioning_end, 1.2, 1e-15);
  EXPECT_NEAR(p.instants().approach_start, 2.0, 1e-15);
  EXPECT_NEAR(p.instants().approach_accel_end, 2.2, 1e-14);
  EXPECT_NEAR(p.instants().touch, 2.2 + 8.8 / 12.0, 1e-14);
  EXPECT_EQ(p.segment_count(), 6);
  expect_valid_profile(p);
}

TEST(MoveProfile, SmoothingIsAJerkLimitOfAccelOverTheSmoothingTime) {
  ProbingMove m = baseline_move();
  m.smoothing = 0.04;  // PA 0.2 -> J 5 m/s^3; AA 0.06 -> J 1.5 m/s^3
  const MoveProfile smoothed = planned(m);
  ProbingMove positioning_jerk = baseline_move();
  positioning_jerk.jerk = 5.0;
  // A moving average over T of a trapezoid's acceleration: each ramp lasts T longer.
  EXPECT_NEAR(smoothed.instants().positioning_accel_end, 0.2 + 0.04, 1e-14);
  EXPECT_NEAR(smoothed.instants().positioning_end, 1.2 + 0.04, 1e-14);
  EXPECT_NEAR(smoothed.instants().positioning_accel_end,
              planned(positioning_jerk).instants().positioning_accel_end,
              1e-15);
  EXPECT_NEAR(smoothed.instants().approach_accel_end - smoothed.instants().approach_start,
              0.2 + 0.04,
              1e-14);
  expect_valid_profile(smoothed);
  // A tighter jerk limit of the move wins over the smoothing's.
  m.jerk = 1.0;
  EXPECT_NEAR(planned(m).sample(0.01).jerk, 1.0, 1e-15);
  expect_valid_profile(planned(m));
}

TEST(MoveProfile, TouchWhileAcceleratingWhenApproachTooShort) {
  ProbingMove m = baseline_move();
  m.approach_distance = 0.0005;  // AV needs 1.2 mm
  const MoveProfile p = planned(m);
  EXPECT_FALSE(p.approach_reaches_speed());
  EXPECT_NEAR(
      p.instants().touch - p.instants().positioning_end, std::sqrt(2 * 0.0005 / 0.060), 1e-15);
  expect_valid_profile(p);
}

TEST(MoveProfile, JerkLimitedSevenSegments) {
  ProbingMove m = baseline_move();
  m.jerk = 2.0;  // reaches PA: ramp = 0.2 + 0.1 s, both ramps 12 mm
  const MoveProfile p = planned(m);
  EXPECT_NEAR(p.instants().positioning_accel_end, 0.3, 1e-15);
  EXPECT_NEAR(p.instants().positioning_end, 0.3 + 0.7 + 0.3, 1e-14);
  EXPECT_EQ(p.segment_count(), 7 + 3 + 1);
  expect_valid_profile(p);
  // AA 60 mm/s^2 with J 2 m/s^3: approach ramp 0.2 + 0.03 s.
  EXPECT_NEAR(p.instants().approach_accel_end - p.instants().positioning_end, 0.23, 1e-14);
}

TEST(MoveProfile, JerkLimitedWithoutReachingAcceleration) {
  ProbingMove m = baseline_move();
  m.jerk = 0.5;  // V J = 0.02 < A^2 = 0.04: the ramp never reaches PA
  const MoveProfile p = planned(m);
  EXPECT_NEAR(p.instants().positioning_accel_end, 2.0 * std::sqrt(0.040 / 0.5), 1e-15);
  const MotionState s = p.sample(std::sqrt(0.040 / 0.5));
  EXPECT_NEAR(s.acceleration, std::sqrt(0.040 * 0.5), 1e-15);
  expect_valid_profile(p);
}

TEST(MoveProfile, JerkLimitedShortDistancesBothCases) {
  ProbingMove m = baseline_move();
  m.jerk = 2.0;
  m.positioning_distance = 0.010;  // peak speed reached with PA held for a while
  m.approach_distance = 0.000005;  // first jerk segment covers 2 * 0.03^3 / 6 = 9 µm
  MoveProfile p = planned(m);
  EXPECT_FALSE(p.positioning_reaches_speed());
  EXPECT_FALSE(p.approach_reaches_speed());
  EXPECT_NEAR(
      p.instants().touch - p.instants().positioning_end, std::cbrt(6 * 0.000005 / 2.0), 1e-14);
  expect_valid_profile(p);
  m.positioning_distance = 0.002;  // so short that PA is never reached
  m.approach_distance = 0.0012;    // the ramp's last jerk segment spans ~1.03..1.38 mm: cubic
  p = planned(m);
  EXPECT_LT(p.sample(p.instants().touch).jerk, 0.0);  // inside the ramp-down segment
  EXPECT_FALSE(p.positioning_reaches_speed());
  EXPECT_LT(p.sample(p.instants().positioning_accel_end / 2).acceleration, 0.2);
  expect_valid_profile(p);
}

TEST(MoveProfile, ApproachFasterThanPositioningIsAllowed) {
  ProbingMove m = baseline_move();
  m.approach_speed = 0.060;
  expect_valid_profile(planned(m));
}

TEST(MoveProfile, RandomMovesHaveExactDistancesAndContinuity) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed());
  auto log_uniform = [&rng](double lo, double hi) {
    return lo * std::pow(hi / lo, std::uniform_real_distribution<double>(0, 1)(rng));
  };
  const int n = test::soak_count(300);
  for (int i = 0; i < n; ++i) {
    ProbingMove m;
    m.positioning_speed = log_uniform(0.005, 0.5);
    m.positioning_accel = log_uniform(0.05, 5.0);
    m.positioning_distance = log_uniform(0.0005, 0.5);
    m.approach_speed = log_uniform(0.001, 0.05);
    m.approach_accel = log_uniform(0.01, 1.0);
    m.approach_distance = log_uniform(0.0001, 0.03);
    m.jerk = (i % 2 == 0) ? 0.0 : log_uniform(0.1, 100.0);
    m.dwell = (i % 3 == 0) ? 0.0 : log_uniform(0.001, 2.0);
    m.smoothing = (i % 4 < 2) ? 0.0 : log_uniform(0.001, 0.2);
    SCOPED_TRACE("case " + std::to_string(i));
    MoveProfile p;
    ASSERT_EQ(MoveProfile::plan(m, p), Status::kOk);
    expect_valid_profile(p);
    if (HasFatalFailure() || HasNonfatalFailure()) return;
  }
}

TEST(MoveProfile, SampleOutsideTheMove) {
  const MoveProfile p = planned(baseline_move());
  const MotionState before = p.sample(-1.0);
  EXPECT_EQ(before.position, 0.0);
  EXPECT_EQ(before.velocity, 0.0);
  const MotionState after = p.sample(p.instants().touch + 0.5);
  EXPECT_NEAR(after.velocity, 0.012, 1e-15);  // still moving at AV
  EXPECT_NEAR(after.position, 0.050 + 0.006, 1e-15);
  const MotionState nan = p.sample(kNaN);
  EXPECT_EQ(nan.position, 0.0);
}

TEST(MoveProfile, RejectsInvalidParametersAndLeavesOutputUntouched) {
  MoveProfile good = planned(baseline_move());
  const double touch = good.instants().touch;
  const double bad_values[] = {0.0, -1.0, kNaN, kInf, -kInf, 1e9, 1e-12};
  for (int field = 0; field < 9; ++field) {
    for (double v : bad_values) {
      ProbingMove m = baseline_move();
      double* fields[] = {&m.positioning_speed,
                          &m.positioning_accel,
                          &m.positioning_distance,
                          &m.approach_speed,
                          &m.approach_accel,
                          &m.approach_distance,
                          &m.jerk,
                          &m.dwell,
                          &m.smoothing};
      if (field == 6 && v == 0.0) continue;                 // jerk 0 means "no jerk limit"
      if (field > 6 && (v == 0.0 || v == 1e-12)) continue;  // dwell, smoothing: 0 = none
      *fields[field] = v;
      EXPECT_EQ(MoveProfile::plan(m, good), Status::kInvalidInput)
          << "field " << field << " value " << v;
      EXPECT_EQ(good.instants().touch, touch);
    }
  }
}

TEST(MoveProfile, LimitsAreInclusive) {
  ProbingMove m = baseline_move();
  m.positioning_distance = MoveLimits::kMaxDistance;
  m.approach_distance = MoveLimits::kMinDistance;
  m.positioning_speed = MoveLimits::kMaxSpeed;
  m.jerk = MoveLimits::kMinJerk;
  MoveProfile p;
  EXPECT_EQ(MoveProfile::plan(m, p), Status::kOk);
  expect_valid_profile(p);
}

}  // namespace
}  // namespace cmmcomp::motion
