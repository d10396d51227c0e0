// SPDX-License-Identifier: MIT
/// @file StaticMoveCompensator (firmware form): the same answers as MoveCompensator, float
/// models, refused publications that keep the old model, and hot swap with an "interrupt"
/// (a POSIX signal handler, which preempts the publishing loop exactly as an ISR does).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/time.h>

#include <array>
#include <chrono>
#include <cmath>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstdint>
#include <limits>
#include <random>

#include "support/compensation_models.hpp"
#include "support/test_seed.hpp"

namespace cmmcomp::compensation {
namespace {

using Model = compensation::Model<PaperInputs>;
using ModelY = compensation::Model<CarriageInputs>;
using test::linear_model;
using test::linear_model_y;

MoveRequest random_move(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  MoveRequest r;
  r.sequence = static_cast<std::uint32_t>(rng());
  r.axis = static_cast<std::uint8_t>(rng() % kMaxAxes);
  r.direction = {0.0, -1.0, 0.0};
  r.pv_mm_s = 1.0 + 100.0 * u(rng);  // partly outside the range [5, 80]: clamped
  r.pa_mm_s2 = 500.0;
  r.pd_mm = 1.0 + 60.0 * u(rng);
  r.av_mm_s = 0.5 + 10.0 * u(rng);
  r.aa_mm_s2 = 200.0;
  r.ad_mm = 0.5 + 5.0 * u(rng);
  r.y_mm = 600.0 * u(rng);
  return r;
}

bool same(const Correction& a, const Correction& b) {
  return a.mpe_um == b.mpe_um && a.rpe_um == b.rpe_um && a.mae_um == b.mae_um &&
         a.rae_um == b.rae_um && a.correction_um == b.correction_um && a.flags == b.flags &&
         a.sequence == b.sequence && a.model_id == b.model_id && a.u95_um == b.u95_um;
}

// Large enough for a static; tests place compensators in static storage as firmware does.
StaticMoveCompensator<Model> g_four;
StaticMoveCompensator<ModelY> g_five;

TEST(StaticMoveCompensator, AnswersExactlyAsMoveCompensator) {
  const Model m4 = linear_model({1.0, -2.0, 3.0, 0.5}, {4.0, 1.0, -1.0, 2.0}, 2);
  const ModelY m5 = linear_model_y({0.5, 1.0, -0.5, 0.25}, {1.0, 2.0, 3.0, -4.0});
  MoveCompensator hosted4;
  MoveCompensator hosted5;
  for (int axis = 0; axis < kMaxAxes; ++axis) {
    ASSERT_EQ(g_four.publish(axis, m4, 40 + axis), Status::kOk);
    ASSERT_EQ(g_five.publish(axis, m5, 50 + axis), Status::kOk);
    ASSERT_EQ(hosted4.publish(axis, m4, 40 + axis), Status::kOk);
    ASSERT_EQ(hosted5.publish(axis, m5, 50 + axis), Status::kOk);
  }
  std::mt19937_64 rng(test::seed());
  for (int k = 0; k < 2000; ++k) {
    const MoveRequest move = random_move(rng);
    Correction a;
    Correction b;
    ASSERT_EQ(g_four.before_approach(move, a), hosted4.before_approach(move, b));
    EXPECT_TRUE(same(a, b)) << "move " << k;
    ASSERT_EQ(g_five.before_approach(move, a), hosted5.before_approach(move, b));
    EXPECT_TRUE(same(a, b)) << "move " << k;
  }
}

// With an interval calibration too: the same U95, in and outside the domain.
TEST(StaticMoveCompensator, CarriesTheIntervalAsMoveCompensator) {
  static StaticMoveCompensator<Model> fw;
  const Model m4 = linear_model({1.0, -2.0, 3.0, 0.5}, {4.0, 1.0, -1.0, 2.0}, 2);
  IntervalCalibration cal;
  cal.coverage = 0.95;
  cal.half_width = {1.0, 2.0, 3.0, 4.0};
  cal.extrapolation_gain = {0.5, 0.0, 1.0, 2.0};
  cal.corner_gain = {1.5, 0.25, 0.0, 3.0};
  MoveCompensator hosted;
  for (int axis = 0; axis < kMaxAxes; ++axis) {
    ASSERT_EQ(fw.publish(axis, m4, cal, 60 + axis), Status::kOk);
    ASSERT_EQ(hosted.publish(axis, m4, cal, 60 + axis), Status::kOk);
  }
  std::mt19937_64 rng(test::seed());
  int outside = 0;
  for (int k = 0; k < 2000; ++k) {
    const MoveRequest move = random_move(rng);
    Correction a;
    Correction b;
    const Status s = fw.before_approach(move, a);
    ASSERT_EQ(s, hosted.before_approach(move, b));
    if (!ok(s)) continue;
    EXPECT_TRUE(same(a, b)) << "move " << k;
    EXPECT_EQ(a.flags & kFlagNoUncertainty, 0u);
    EXPECT_GE(a.u95_um[3], cal.half_width[3]);
    if (s == Status::kOutsideDomain) {
      ++outside;
      EXPECT_GT(a.u95_um[3], cal.half_width[3]) << "move " << k;
    }
  }
  EXPECT_GT(outside, 0) << "the random moves should leave the domain sometimes";
  IntervalCalibration bad = cal;
  bad.extrapolation_gain[1] = std::nan("");
  EXPECT_EQ(fw.publish(0, m4, bad, 99), Status::kInvalidInput);
  EXPECT_EQ(fw.model_id(0), 60u);
}

TEST(StaticMoveCompensator, NoModelInvalidInputAndBadAxis) {
  static StaticMoveCompensator<Model> c;
  std::mt19937_64 rng(test::seed());
  MoveRequest move = random_move(rng);
  Correction out;
  EXPECT_FALSE(c.has_model(move.axis));
  EXPECT_EQ(c.model_id(move.axis), 0u);
  EXPECT_EQ(c.before_approach(move, out), Status::kNoModel);
  const Model m = linear_model({1, 2, 3, 4}, {0, 0, 0, 0});
  EXPECT_EQ(c.publish(-1, m), Status::kInvalidInput);
  EXPECT_EQ(c.publish(kMaxAxes, m), Status::kInvalidInput);
  ASSERT_EQ(c.publish(move.axis, m, 9), Status::kOk);
  EXPECT_TRUE(c.has_model(move.axis));
  EXPECT_EQ(c.model_id(move.axis), 9u);
  move.pv_mm_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(c.before_approach(move, out), Status::kInvalidInput);
  move.pv_mm_s = 20.0;
  move.direction = {0.5, 0.0, 0.0};
  EXPECT_EQ(c.before_approach(move, out), Status::kInvalidInput);
}

TEST(StaticMoveCompensator, AxesBeyondTheCompiledCountAreInvalid) {
  static StaticMoveCompensator<Model, 2> c;
  EXPECT_EQ(c.publish(2, linear_model({1, 2, 3, 4}, {0, 0, 0, 0})), Status::kInvalidInput);
  MoveRequest move;
  move.axis = 2;
  move.pv_mm_s = move.pa_mm_s2 = move.pd_mm = move.av_mm_s = move.aa_mm_s2 = move.ad_mm = 1.0;
  Correction out;
  EXPECT_EQ(c.before_approach(move, out), Status::kInvalidInput);
}

TEST(StaticMoveCompensator, ARefusedModelKeepsTheOldOneServing) {
  static StaticMoveCompensator<Model> c;
  const Model good = linear_model({1, 2, 3, 4}, {0, 0, 0, 0});
  ASSERT_EQ(c.publish(0, good, 1), Status::kOk);
  Model bad = good;
  bad.params.width(2, 1) = 0.0;
  fuzzy::ModelProblem problem;
  EXPECT_EQ(c.publish(0, bad, 2, &problem), Status::kInvalidInput);
  EXPECT_EQ(problem.kind, fuzzy::ModelProblem::kWidthNotPositive);
  EXPECT_EQ(problem.input, 2);
  EXPECT_EQ(problem.set, 1);
  bad = good;
  bad.params.values[100] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(c.publish(0, bad, 3, &problem), Status::kInvalidInput);
  EXPECT_EQ(problem.kind, fuzzy::ModelProblem::kParamNotFinite);
  EXPECT_EQ(problem.index, 100);
  bad = good;
  bad.ranges[1] = {3.0, 3.0};
  EXPECT_EQ(c.publish(0, bad, 4, &problem), Status::kInvalidInput);
  EXPECT_EQ(problem.kind, fuzzy::ModelProblem::kRangeEmpty);
  EXPECT_EQ(c.model_id(0), 1u);
  std::mt19937_64 rng(test::seed());
  MoveRequest move = random_move(rng);
  move.axis = 0;
  Correction out;
  ASSERT_TRUE(ok(c.before_approach(move, out)));
  EXPECT_EQ(out.model_id, 1u);
  EXPECT_DOUBLE_EQ(out.rae_um, 4.0);
}

TEST(StaticMoveCompensator, ServesAFloatModelWithinAMicronThousandth) {
  const Model m = linear_model({1.5, -2.25, 3.0, 0.75}, {4.0, 1.0, -1.0, 2.0}, 1);
  static StaticMoveCompensator<compensation::Model<PaperInputs, float>> c32;
  MoveCompensator c64;
  ASSERT_EQ(c32.publish(0, fuzzy::convert_model<float>(m), 5), Status::kOk);
  ASSERT_EQ(c64.publish(0, m, 5), Status::kOk);
  std::mt19937_64 rng(test::seed());
  for (int k = 0; k < 1000; ++k) {
    MoveRequest move = random_move(rng);
    move.axis = 0;
    Correction a;
    Correction b;
    ASSERT_EQ(c32.before_approach(move, a), c64.before_approach(move, b));
    EXPECT_NEAR(a.mpe_um, b.mpe_um, 1e-3);
    EXPECT_NEAR(a.rpe_um, b.rpe_um, 1e-3);
    EXPECT_NEAR(a.mae_um, b.mae_um, 1e-3);
    EXPECT_NEAR(a.rae_um, b.rae_um, 1e-3);
  }
}

// A model whose RAE is finite but so large that RAE·d overflows (|d| may exceed 1 by
// kDirectionTolerance) gave ok with an infinite correction (issue 16, D7). Only the corner rule
// fires (widths 0.01), so the output is the consequent constant exactly.
TEST(Compensators, NeverReturnAnInfiniteCorrection) {
  Model m = linear_model({0, 0, 0, 0}, {0, 0, 0, 0});
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) m.params.width(i, s) = 0.01;
  }
  for (int j = 0; j < Model::kRules; ++j) {
    m.params.consequent(3, j, 0) = std::numeric_limits<double>::max() * 0.9999999;
  }
  MoveRequest move;
  move.axis = 0;
  move.direction = {1.0 + 9e-7, 0.0, 0.0};  // |d| = 1 + 9e-7, accepted
  move.pv_mm_s = 5.0;                       // every input at its range's low end: rule 0 alone
  move.pd_mm = 1.0;
  move.av_mm_s = 1.0;
  move.ad_mm = 0.5;
  move.pa_mm_s2 = move.aa_mm_s2 = 100.0;
  MoveCompensator hosted;
  static StaticMoveCompensator<Model> firmware;
  ASSERT_EQ(hosted.publish(0, m), Status::kOk);
  ASSERT_EQ(firmware.publish(0, m), Status::kOk);
  const Correction untouched;
  Correction a = untouched;
  Correction b = untouched;
  EXPECT_EQ(hosted.before_approach(move, a), Status::kInvalidInput);
  EXPECT_EQ(firmware.before_approach(move, b), Status::kInvalidInput);
  EXPECT_TRUE(same(a, untouched));
  EXPECT_TRUE(same(b, untouched));
  move.direction = {1.0, 0.0, 0.0};  // exactly 1: RAE·d = RAE, finite
  EXPECT_TRUE(ok(hosted.before_approach(move, a)));
  EXPECT_TRUE(std::isfinite(a.correction_um[0]));
}

// --- Hot swap with an interrupt --------------------------------------------------------------
// The main loop publishes models A (id 1) and B (id 2) alternately; a SIGALRM handler (which,
// like an ISR, runs to completion before the interrupted code resumes) calls before_approach and
// checks that the correction is exactly A's or B's, as its model id says.
StaticMoveCompensator<Model> g_swap;
MoveRequest g_move;
Correction g_expected[3];
volatile sig_atomic_t g_in_publish = 0;
volatile sig_atomic_t g_calls = 0;
volatile sig_atomic_t g_calls_in_publish = 0;
volatile sig_atomic_t g_wrong = 0;

void on_alarm(int) {
  Correction out;
  const Status s = g_swap.before_approach(g_move, out);
  g_calls = g_calls + 1;
  if (g_in_publish) g_calls_in_publish = g_calls_in_publish + 1;
  if (!ok(s) || out.model_id < 1 || out.model_id > 2 || !same(out, g_expected[out.model_id])) {
    g_wrong = g_wrong + 1;
  }
}

TEST(StaticMoveCompensator, HotSwapUnderAnInterruptNeverMixesModels) {
  const Model a = linear_model({1, 2, 3, 4}, {0.5, 0.5, 0.5, 0.5});
  const Model b = linear_model({-7, -6, -5, -4}, {2, 2, 2, 2}, 3);
  std::mt19937_64 rng(test::seed());
  g_move = random_move(rng);
  g_move.axis = 1;
  {
    static StaticMoveCompensator<Model> reference;
    ASSERT_EQ(reference.publish(1, a, 1), Status::kOk);
    ASSERT_TRUE(ok(reference.before_approach(g_move, g_expected[1])));
    ASSERT_EQ(reference.publish(1, b, 2), Status::kOk);
    ASSERT_TRUE(ok(reference.before_approach(g_move, g_expected[2])));
    ASSERT_NE(g_expected[1].rae_um, g_expected[2].rae_um);
  }
  ASSERT_EQ(g_swap.publish(1, a, 1), Status::kOk);

  struct sigaction action {};
  action.sa_handler = on_alarm;
  sigemptyset(&action.sa_mask);
  ASSERT_EQ(sigaction(SIGALRM, &action, nullptr), 0);
  const itimerval every_50us{{0, 50}, {0, 50}};
  ASSERT_EQ(setitimer(ITIMER_REAL, &every_50us, nullptr), 0);
  // Waits for what it needs (interrupts that land inside a publish), not for a time; the
  // deadline only turns a machine that never delivers one into a failure instead of a hang.
  constexpr int kNeeded = 200;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
  long publishes = 0;
  bool refused = false;
  while (g_calls_in_publish < kNeeded && std::chrono::steady_clock::now() < deadline) {
    g_in_publish = 1;
    refused |=
        g_swap.publish(1, publishes % 2 == 0 ? b : a, publishes % 2 == 0 ? 2 : 1) != Status::kOk;
    g_in_publish = 0;
    ++publishes;
  }
  const itimerval off{};
  setitimer(ITIMER_REAL, &off, nullptr);
  signal(SIGALRM, SIG_DFL);
  EXPECT_GE(g_calls_in_publish, kNeeded) << "interrupts inside a publish (machine too slow?)";
  EXPECT_EQ(g_wrong, 0) << "of " << g_calls << " interrupt calls";
  EXPECT_FALSE(refused) << "publish returned kBusy although every reader preempts it";
}

TEST(FindProblem, ChecksAConstexprModelAtCompileTime) {
  constexpr auto model = [] {
    fuzzy::TskModel<float, 4, 3, 4> m{};
    for (auto& r : m.ranges) r = {0.0, 1.0};
    for (int i = 0; i < 4; ++i) {
      for (int s = 0; s < 3; ++s) m.params.width(i, s) = 0.4f;
    }
    return m;
  }();
  static_assert(!fuzzy::find_problem(model), "a firmware image can reject a bad model at build");
  constexpr auto empty = fuzzy::TskModel<double, 4, 3, 4>{};
  static_assert(fuzzy::find_problem(empty).kind == fuzzy::ModelProblem::kWidthNotPositive);
  SUCCEED();
}

}  // namespace
}  // namespace cmmcomp::compensation
