// SPDX-License-Identifier: MIT
/// @file MPE, RPE, MAE, RAE from synthetic traces with known answers.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <limits>
#include <vector>

namespace cmmcomp::errors {
namespace {

// Instants of the baseline move: accel end 0.2, decel start 1.0, positioning end = approach
// start 1.2 (no dwell), approach accel end 1.4, touch 2.1333 s.
motion::PhaseInstants baseline_instants() {
  motion::MoveProfile p;
  EXPECT_EQ(motion::MoveProfile::plan(motion::baseline_move(), p), Status::kOk);
  return p.instants();
}

struct Trace {
  std::vector<double> t, e;
  TraceView view() const { return TraceView{t.data(), e.data(), t.size()}; }
};

template <typename F>
Trace sampled(F f, double t_end, int n) {
  Trace tr;
  for (int i = 0; i <= n; ++i) {
    const double t = t_end * i / n;
    tr.t.push_back(t);
    tr.e.push_back(f(t));
  }
  return tr;
}

TEST(DynamicErrors, PiecewiseLinearTraceGivesExactValues) {
  const motion::PhaseInstants in = baseline_instants();
  // Knots away from the instants, so the values at the instants come from interpolation.
  Trace tr;
  tr.t = {0.0, 0.3, 0.7, 0.9, 1.1, 1.25, 1.3, 1.5, 2.0, 2.2};
  tr.e = {0.0, -4.0, 13.5, -8.0, -4.0, 2.0, -7.0, -1.0, 3.0, 5.0};
  DynamicErrors out;
  ASSERT_EQ(extract_dynamic_errors(tr.view(), in, +1, out), Status::kOk);
  EXPECT_DOUBLE_EQ(out.mpe, 13.5);
  EXPECT_DOUBLE_EQ(out.rpe, -6.0);  // at the deceleration start, halfway between -8 and -4
  EXPECT_DOUBLE_EQ(out.mae, 7.0);
  const double w = (in.touch - 2.0) / 0.2;
  EXPECT_DOUBLE_EQ(out.rae, 3.0 + w * 2.0);
}

TEST(DynamicErrors, PhaseEndsCountTowardsTheMaxima) {
  const motion::PhaseInstants in = baseline_instants();
  // |e| peaks exactly at the positioning end (1.2 s) between samples 1.1 and 1.3.
  Trace tr;
  tr.t = {0.0, 1.1, 1.3, 2.2};
  tr.e = {0.0, 9.0, 9.0, 0.0};
  DynamicErrors out;
  ASSERT_EQ(extract_dynamic_errors(tr.view(), in, +1, out), Status::kOk);
  EXPECT_DOUBLE_EQ(out.mpe, 9.0);
  EXPECT_DOUBLE_EQ(out.mae, 9.0);
}

TEST(DynamicErrors, SmoothTraceConvergesToAnalyticValues) {
  const motion::PhaseInstants in = baseline_instants();
  // e(t) = 10 sin(2π t / 1.2) on positioning, then 4 exp(-(t-1.2)) cos(...) on approach.
  auto f = [](double t) {
    const double kPi = 3.14159265358979323846;
    return t <= 1.2 ? 10.0 * std::sin(2 * kPi * t / 1.2)
                    : 6.0 * std::sin(2 * kPi * (t - 1.2) / 0.8) * std::exp(-(t - 1.2));
  };
  const Trace tr = sampled(f, 2.2, 22000);
  DynamicErrors out;
  ASSERT_EQ(extract_dynamic_errors(tr.view(), in, +1, out), Status::kOk);
  EXPECT_NEAR(out.mpe, 10.0, 1e-5);
  EXPECT_NEAR(out.rpe, f(in.positioning_decel_start), 1e-6);
  EXPECT_NEAR(out.rae, f(in.touch), 1e-6);
  // Approach maximum: brute force on a much finer grid.
  double mae = 0;
  for (int i = 0; i <= 1000000; ++i) {
    mae = std::max(mae, std::fabs(f(1.2 + (in.touch - 1.2) * i / 1e6)));
  }
  EXPECT_NEAR(out.mae, mae, 1e-5);
}

TEST(DynamicErrors, DirectionSignsOnlyTheResiduals) {
  const motion::PhaseInstants in = baseline_instants();
  const Trace tr = sampled([](double t) { return 2.0 + t; }, 2.2, 220);
  DynamicErrors fwd, back;
  ASSERT_EQ(extract_dynamic_errors(tr.view(), in, +1, fwd), Status::kOk);
  ASSERT_EQ(extract_dynamic_errors(tr.view(), in, -1, back), Status::kOk);
  EXPECT_DOUBLE_EQ(fwd.mpe, back.mpe);
  EXPECT_DOUBLE_EQ(fwd.mae, back.mae);
  EXPECT_DOUBLE_EQ(fwd.rpe, -back.rpe);
  EXPECT_DOUBLE_EQ(fwd.rae, -back.rae);
  EXPECT_NEAR(fwd.rpe, 2.0 + in.positioning_decel_start, 1e-12);
  EXPECT_NEAR(fwd.rae, 2.0 + in.touch, 1e-12);
}

TEST(DynamicErrors, RpeIsReadAtTheDecelerationStartAndMaeAfterTheDwell) {
  motion::ProbingMove move = motion::baseline_move();
  move.dwell = 0.5;
  motion::MoveProfile p;
  ASSERT_EQ(motion::MoveProfile::plan(move, p), Status::kOk);
  const motion::PhaseInstants in = p.instants();
  ASSERT_NEAR(in.positioning_decel_start, 1.0, 1e-12);
  ASSERT_NEAR(in.approach_start, 1.7, 1e-12);
  // A spike during the dwell (at rest at the pre-hit point) is outside both maximum windows.
  Trace tr;
  tr.t = {0.0, 0.2, 1.0, 1.2, 1.45, 1.7, 2.0, in.touch};
  tr.e = {0.0, 3.0, -2.5, 1.0, 20.0, 1.0, -4.0, -3.0};
  DynamicErrors out;
  ASSERT_EQ(extract_dynamic_errors(tr.view(), in, +1, out), Status::kOk);
  EXPECT_DOUBLE_EQ(out.rpe, -2.5);
  EXPECT_DOUBLE_EQ(out.mpe, 3.0);
  EXPECT_DOUBLE_EQ(out.mae, 4.0);
  EXPECT_DOUBLE_EQ(out.rae, -3.0);
}

TEST(DynamicErrors, RejectsBadTracesAndLeavesOutputUntouched) {
  const motion::PhaseInstants in = baseline_instants();
  const DynamicErrors sentinel{1, 2, 3, 4};
  auto expect = [&](const Trace& tr, int dir, Status want) {
    DynamicErrors out = sentinel;
    EXPECT_EQ(extract_dynamic_errors(tr.view(), in, dir, out), want);
    EXPECT_EQ(out.mpe, 1);
    EXPECT_EQ(out.rae, 4);
  };
  const Trace good = sampled([](double t) { return t; }, 2.2, 100);
  expect(good, 0, Status::kInvalidInput);
  expect(good, 2, Status::kInvalidInput);
  Trace nan = good;
  nan.e[50] = std::numeric_limits<double>::quiet_NaN();
  expect(nan, 1, Status::kInvalidInput);
  Trace inf_time = good;
  inf_time.t[100] = std::numeric_limits<double>::infinity();
  expect(inf_time, 1, Status::kInvalidInput);
  Trace unsorted = good;
  std::swap(unsorted.t[10], unsorted.t[11]);
  expect(unsorted, 1, Status::kInvalidInput);
  Trace repeated = good;
  repeated.t[11] = repeated.t[10];
  expect(repeated, 1, Status::kInvalidInput);
  expect(sampled([](double t) { return t; }, 2.0, 100), 1, Status::kTraceTooShort);  // ends early
  Trace late_start = good;
  late_start.t[0] = 0.001;
  expect(late_start, 1, Status::kTraceTooShort);
  Trace one;
  one.t = {0.0};
  one.e = {0.0};
  expect(one, 1, Status::kTraceTooShort);
  expect(Trace{}, 1, Status::kTraceTooShort);

  motion::PhaseInstants disordered = in;
  disordered.positioning_end = in.touch + 1;
  DynamicErrors out = sentinel;
  EXPECT_EQ(extract_dynamic_errors(good.view(), disordered, 1, out), Status::kInvalidInput);
  EXPECT_EQ(out.mpe, 1);
  motion::PhaseInstants decel_before_accel = in;
  decel_before_accel.positioning_decel_start = in.positioning_accel_end / 2;
  EXPECT_EQ(extract_dynamic_errors(good.view(), decel_before_accel, 1, out), Status::kInvalidInput);
  motion::PhaseInstants approach_before_stop = in;
  approach_before_stop.approach_start = in.positioning_end / 2;
  EXPECT_EQ(extract_dynamic_errors(good.view(), approach_before_stop, 1, out),
            Status::kInvalidInput);
  EXPECT_EQ(out.mpe, 1);
}

}  // namespace
}  // namespace cmmcomp::errors
