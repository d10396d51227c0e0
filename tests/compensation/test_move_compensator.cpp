// SPDX-License-Identifier: MIT
/// @file MoveCompensator: corrections against hand-built models, signs, invalid input, no model,
/// refused publications and hot swap under concurrency.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <string>
#include <thread>

#include "support/compensation_models.hpp"
#include "support/test_seed.hpp"

namespace cmmcomp::compensation {
namespace {

using Model = compensation::Model<PaperInputs>;

using test::linear_model;

Model random_model(std::mt19937_64& rng) {
  Model m = linear_model({0, 0, 0, 0}, {0, 0, 0, 0});
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (int k = Model::Params::kConsequentsOffset; k < Model::kParamCount; ++k) {
    m.params.values[static_cast<unsigned>(k)] = u(rng);
  }
  return m;
}

MoveRequest move_at(double pv_mm_s) {
  MoveRequest r;
  r.sequence = 7;
  r.axis = 0;
  r.direction = {1.0, 0.0, 0.0};
  r.pv_mm_s = pv_mm_s;
  r.pa_mm_s2 = 500.0;
  r.pd_mm = 20.0;
  r.av_mm_s = 5.0;
  r.aa_mm_s2 = 200.0;
  r.ad_mm = 2.0;
  r.y_mm = 300.0;
  r.z_mm = -100.0;
  return r;
}

Correction sentinel() {
  Correction c;
  c.mpe_um = c.rpe_um = c.mae_um = c.rae_um = -999.0;
  c.correction_um = {-999.0, -999.0, -999.0};
  c.flags = 0xdeadu;
  c.sequence = 0xbeefu;
  c.model_id = 0x1234u;
  return c;
}

bool same_bits(const Correction& a, const Correction& b) {
  return std::memcmp(&a.mpe_um, &b.mpe_um, 4 * sizeof(double)) == 0 &&
         a.correction_um == b.correction_um && a.flags == b.flags && a.sequence == b.sequence &&
         a.model_id == b.model_id;
}

TEST(CompensatorOptions, DefaultsAreValidAndClamp) {
  const CompensatorOptions o;
  std::string why;
  EXPECT_TRUE(o.is_valid(&why));
  EXPECT_EQ(o.outside_domain, fuzzy::DomainPolicy::kClamp);
}

TEST(CompensatorOptions, RejectsUnknownPolicyAndConstructorThrows) {
  CompensatorOptions o;
  o.outside_domain = static_cast<fuzzy::DomainPolicy>(42);
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_NE(why.find("outside_domain"), std::string::npos);
  EXPECT_THROW(MoveCompensator{o}, ConfigError);
}

TEST(MoveCompensator, ComputesHandBuiltModel) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, linear_model({3.0, -1.25, 4.0, 2.5}, {1.0, 0.5, 0.0, 2.0}), 0xabcu),
            Status::kOk);
  Correction out;
  // PV = 42.5 mm/s is the middle of [5, 80]: x̂ = 0.5.
  ASSERT_EQ(comp.before_approach(move_at(42.5), out), Status::kOk);
  EXPECT_NEAR(out.mpe_um, 3.5, 1e-12);
  EXPECT_NEAR(out.rpe_um, -1.0, 1e-12);
  EXPECT_NEAR(out.mae_um, 4.0, 1e-12);
  EXPECT_NEAR(out.rae_um, 3.5, 1e-12);
  EXPECT_NEAR(out.correction_um[0], 3.5, 1e-12);
  EXPECT_EQ(out.correction_um[1], 0.0);
  EXPECT_EQ(out.correction_um[2], 0.0);
  // A model built in code has no interval calibration: flagged, and U95 reads 0 ("unknown").
  EXPECT_EQ(out.flags, kFlagOk | kFlagNoUncertainty);
  for (const double u : out.u95_um) EXPECT_EQ(u, 0.0);
  EXPECT_EQ(out.sequence, 7u);
  EXPECT_EQ(out.model_id, 0xabcu);
}

// A 5-input model reads the carriage position; publishing either kind replaces the other.
TEST(MoveCompensator, FiveInputModelReadsTheCarriagePosition) {
  MoveCompensator comp;
  EXPECT_EQ(comp.model_inputs(0), 0);
  ASSERT_EQ(comp.publish(0, test::linear_model_y({1.0, 2.0, 3.0, 4.0}, {0, 0, 0, 2.0}), 0x55u),
            Status::kOk);
  EXPECT_EQ(comp.model_inputs(0), 5);
  EXPECT_EQ(comp.model_id(0), 0x55u);
  Correction out;
  MoveRequest m = move_at(42.5);
  for (const double y : {0.0, 125.0, 500.0}) {
    m.y_mm = y;
    ASSERT_EQ(comp.before_approach(m, out), Status::kOk);
    EXPECT_NEAR(out.rae_um, 4.0 + 2.0 * y / 500.0, 1e-12) << "y " << y;
    EXPECT_NEAR(out.mpe_um, 1.0, 1e-12);
    EXPECT_EQ(out.model_id, 0x55u);
  }
  m.y_mm = 540.0;  // outside [0, 500], not far: clamped and flagged, as any input
  ASSERT_EQ(comp.before_approach(m, out), Status::kOutsideDomain);
  EXPECT_NEAR(out.rae_um, 6.0, 1e-12);
  EXPECT_EQ(out.flags, kFlagOk | kFlagOutsideDomain | kFlagNoUncertainty);
  m.y_mm = 900.0;  // far outside (more than 50 mm beyond): refused, as any input
  ASSERT_EQ(comp.before_approach(m, out), Status::kOutsideDomainRejected);

  ASSERT_EQ(comp.publish(0, linear_model({3.0, -1.25, 4.0, 2.5}, {0, 0, 0, 0}), 0x44u),
            Status::kOk);
  EXPECT_EQ(comp.model_inputs(0), 4);
  ASSERT_EQ(comp.before_approach(m, out), Status::kOk);  // Y is no input any more
  EXPECT_NEAR(out.rae_um, 2.5, 1e-12);
  EXPECT_EQ(out.model_id, 0x44u);
}

TEST(MoveCompensator, MatchesFuzzyEvaluateExactly) {
  std::mt19937_64 rng(test::seed());
  const Model m = random_model(rng);
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(2, m), Status::kOk);
  MoveRequest r = move_at(33.0);
  r.axis = 2;
  Correction out;
  ASSERT_EQ(comp.before_approach(r, out), Status::kOk);
  Model::RawOutput y;
  ASSERT_EQ(
      fuzzy::evaluate(m, {r.pv_mm_s, r.pd_mm, r.av_mm_s, r.ad_mm}, y, fuzzy::DomainPolicy::kClamp),
      Status::kOk);
  EXPECT_EQ(out.mpe_um, y[0]);
  EXPECT_EQ(out.rpe_um, y[1]);
  EXPECT_EQ(out.mae_um, y[2]);
  EXPECT_EQ(out.rae_um, y[3]);
}

// Hand example (docs/compensator.md, "Signs"): a probe approaches a face in −x. The scale
// latches 100.000 mm, but the tip, running ahead, touched at 99.998 mm. The trace
// e = (x_tip − x_scale)·d gives RAE = (99.998 − 100.000 mm)·(−1) = +2 µm; the correction
// +RAE·d = (−2, 0, 0) µm added to the scale point gives the tip's point.
TEST(MoveCompensatorSigns, CorrectionIsPlusRaeAlongDirection) {
  const double scale_mm = 100.000;
  const double tip_mm = 99.998;
  const double time[2] = {0.0, 1.0};
  const double raw_um[2] = {0.0, (tip_mm - scale_mm) * 1000.0};  // x_tip − x_scale, axis frame
  errors::DynamicErrors e;
  motion::PhaseInstants at;
  at.positioning_accel_end = 0.2;
  at.positioning_decel_start = 0.3;
  at.positioning_end = 0.5;
  at.approach_start = 0.5;
  at.approach_accel_end = 0.7;
  at.touch = 1.0;
  ASSERT_EQ(errors::extract_dynamic_errors({time, raw_um, 2}, at, -1, e), Status::kOk);
  EXPECT_NEAR(e.rae, 2.0, 1e-9);  // tip ahead of the scale in the direction of motion

  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, linear_model({0.0, 0.0, 0.0, e.rae}, {0.0, 0.0, 0.0, 0.0})),
            Status::kOk);
  MoveRequest r = move_at(40.0);
  r.direction = {-1.0, 0.0, 0.0};
  Correction out;
  ASSERT_EQ(comp.before_approach(r, out), Status::kOk);
  EXPECT_NEAR(out.correction_um[0], -2.0, 1e-9);
  EXPECT_NEAR(scale_mm + out.correction_um[0] / 1000.0, tip_mm, 1e-12);

  // An oblique approach: the correction lies along d and its length is |RAE|.
  const double h = std::sqrt(0.5);
  r.direction = {0.0, h, -h};
  ASSERT_EQ(comp.before_approach(r, out), Status::kOk);
  EXPECT_EQ(out.correction_um[0], 0.0);
  EXPECT_NEAR(out.correction_um[1], 2.0 * h, 1e-9);
  EXPECT_NEAR(out.correction_um[2], -2.0 * h, 1e-9);
}

TEST(MoveCompensatorSigns, NegativeRaeCorrectsAgainstTheDirection) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(1, linear_model({0.0, 0.0, 0.0, -1.5}, {0.0, 0.0, 0.0, 0.0})),
            Status::kOk);
  MoveRequest r = move_at(40.0);
  r.axis = 1;
  r.direction = {0.0, 1.0, 0.0};  // +y; tip lags the scale by 1.5 µm
  Correction out;
  ASSERT_EQ(comp.before_approach(r, out), Status::kOk);
  EXPECT_NEAR(out.correction_um[1], -1.5, 1e-12);
}

TEST(MoveCompensator, RejectsInvalidRequestsAndLeavesOutputUntouched) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, linear_model({1, 2, 3, 4}, {0, 0, 0, 0})), Status::kOk);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  double MoveRequest::*positive[] = {&MoveRequest::pv_mm_s,
                                     &MoveRequest::pa_mm_s2,
                                     &MoveRequest::pd_mm,
                                     &MoveRequest::av_mm_s,
                                     &MoveRequest::aa_mm_s2,
                                     &MoveRequest::ad_mm};
  for (auto field : positive) {
    for (double bad : {nan, inf, -inf, 0.0, -1.0}) {
      MoveRequest r = move_at(40.0);
      r.*field = bad;
      Correction out = sentinel();
      EXPECT_EQ(comp.before_approach(r, out), Status::kInvalidInput) << bad;
      EXPECT_TRUE(same_bits(out, sentinel()));
    }
  }
  for (double bad : {nan, inf}) {
    MoveRequest r = move_at(40.0);
    r.y_mm = bad;
    Correction out = sentinel();
    EXPECT_EQ(comp.before_approach(r, out), Status::kInvalidInput);
    r = move_at(40.0);
    r.z_mm = bad;
    EXPECT_EQ(comp.before_approach(r, out), Status::kInvalidInput);
    r = move_at(40.0);
    r.direction[1] = bad;
    EXPECT_EQ(comp.before_approach(r, out), Status::kInvalidInput);
    EXPECT_TRUE(same_bits(out, sentinel()));
  }
  const std::array<std::array<double, 3>, 4> bad_dirs{
      {{0.0, 0.0, 0.0}, {1.0 + 2e-6, 0.0, 0.0}, {0.6, 0.6, 0.6}, {-1.0 + 2e-6, 0.0, 0.0}}};
  for (const auto& d : bad_dirs) {
    MoveRequest r = move_at(40.0);
    r.direction = d;
    Correction out = sentinel();
    EXPECT_EQ(comp.before_approach(r, out), Status::kInvalidInput);
    EXPECT_TRUE(same_bits(out, sentinel()));
  }
  MoveRequest r = move_at(40.0);
  r.direction = {1.0 + 0.5e-6, 0.0, 0.0};  // inside the tolerance
  Correction out;
  EXPECT_EQ(comp.before_approach(r, out), Status::kOk);
  r.axis = kMaxAxes;
  out = sentinel();
  EXPECT_EQ(comp.before_approach(r, out), Status::kInvalidInput);
  EXPECT_TRUE(same_bits(out, sentinel()));
}

TEST(MoveCompensator, ReportsNoModelPerAxis) {
  MoveCompensator comp;
  Correction out = sentinel();
  EXPECT_FALSE(comp.has_model(0));
  EXPECT_EQ(comp.before_approach(move_at(40.0), out), Status::kNoModel);
  EXPECT_TRUE(same_bits(out, sentinel()));
  ASSERT_EQ(comp.publish(3, linear_model({1, 2, 3, 4}, {0, 0, 0, 0})), Status::kOk);
  EXPECT_TRUE(comp.has_model(3));
  EXPECT_EQ(comp.before_approach(move_at(40.0), out), Status::kNoModel);  // axis 0 still empty
  MoveRequest r = move_at(40.0);
  r.axis = 3;
  EXPECT_EQ(comp.before_approach(r, out), Status::kOk);
}

TEST(MoveCompensator, RefusesInvalidModelAndKeepsServingTheOld) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, linear_model({1, 2, 3, 4}, {0, 0, 0, 0}), 11u), Status::kOk);
  Model bad = linear_model({9, 9, 9, 9}, {0, 0, 0, 0});
  bad.params.width(1, 2) = 0.0;
  std::string why;
  EXPECT_EQ(comp.publish(0, bad, 22u, &why), Status::kInvalidInput);
  EXPECT_NE(why.find("width"), std::string::npos);
  bad = linear_model({9, 9, 9, 9}, {0, 0, 0, 0});
  bad.ranges[0].lo = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(comp.publish(0, bad, 22u), Status::kInvalidInput);
  EXPECT_EQ(comp.publish(-1, linear_model({1, 2, 3, 4}, {0, 0, 0, 0})), Status::kInvalidInput);
  EXPECT_EQ(comp.publish(kMaxAxes, linear_model({1, 2, 3, 4}, {0, 0, 0, 0})),
            Status::kInvalidInput);
  Correction out;
  ASSERT_EQ(comp.before_approach(move_at(40.0), out), Status::kOk);
  EXPECT_NEAR(out.rae_um, 4.0, 1e-12);
  EXPECT_EQ(out.model_id, 11u);
}

TEST(MoveCompensator, AppliesTheDomainPolicy) {
  const Model m = linear_model({0, 0, 0, 1.0}, {0, 0, 0, 2.0});
  MoveCompensator clamp;
  ASSERT_EQ(clamp.publish(0, m), Status::kOk);
  Correction out;
  ASSERT_EQ(clamp.before_approach(move_at(84.0), out), Status::kOutsideDomain);
  EXPECT_EQ(out.flags, kFlagOk | kFlagOutsideDomain | kFlagNoUncertainty);
  EXPECT_NEAR(out.rae_um, 3.0, 1e-12);  // PV clamped to 80: x̂ = 1

  CompensatorOptions o;
  o.outside_domain = fuzzy::DomainPolicy::kExtrapolate;
  MoveCompensator extrapolate(o);
  ASSERT_EQ(extrapolate.publish(0, m), Status::kOk);
  ASSERT_EQ(extrapolate.before_approach(move_at(83.75), out), Status::kOutsideDomain);
  EXPECT_NEAR(out.rae_um, 3.1, 1e-12);  // x̂ = 1.05

  o.outside_domain = fuzzy::DomainPolicy::kReject;
  MoveCompensator reject(o);
  ASSERT_EQ(reject.publish(0, m), Status::kOk);
  out = sentinel();
  EXPECT_EQ(reject.before_approach(move_at(84.0), out), Status::kOutsideDomainRejected);
  EXPECT_TRUE(same_bits(out, sentinel()));
  EXPECT_EQ(reject.before_approach(move_at(40.0), out), Status::kOk);
}

TEST(CorrectionFlags, DescribeEveryStatus) {
  EXPECT_EQ(flags_for(Status::kOk), kFlagOk);
  EXPECT_EQ(flags_for(Status::kOutsideDomain), kFlagOk | kFlagOutsideDomain);
  EXPECT_EQ(flags_for(Status::kOutsideDomainRejected), kFlagOutsideDomain);
  EXPECT_EQ(flags_for(Status::kNoModel), kFlagNoModel);
  EXPECT_EQ(flags_for(Status::kInvalidInput), kFlagInvalidInput);
}

// A reader calls before_approach in a loop while the writer publishes two models alternately:
// every result is bit-identical to one model's output, never a mix of both buffers.
TEST(MoveCompensatorHotSwap, ReaderSeesOneWholeModelAtATime) {
  std::mt19937_64 rng(test::seed());
  const Model a = random_model(rng);
  const Model b = random_model(rng);
  const MoveRequest r = move_at(27.0);
  const Model::RawInput x{r.pv_mm_s, r.pd_mm, r.av_mm_s, r.ad_mm};
  Model::RawOutput ya;
  Model::RawOutput yb;
  ASSERT_EQ(fuzzy::evaluate(a, x, ya, fuzzy::DomainPolicy::kClamp), Status::kOk);
  ASSERT_EQ(fuzzy::evaluate(b, x, yb, fuzzy::DomainPolicy::kClamp), Status::kOk);
  ASSERT_NE(ya[3], yb[3]);

  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, a, 1u), Status::kOk);
  std::atomic<bool> done{false};
  std::atomic<std::uint64_t> calls{0};
  std::atomic<std::uint64_t> mixed{0};
  std::atomic<std::uint64_t> seen_a{0};
  std::atomic<std::uint64_t> seen_b{0};
  std::thread reader([&] {
    Correction out;
    while (!done.load(std::memory_order_acquire)) {
      if (comp.before_approach(r, out) != Status::kOk) {
        mixed.fetch_add(1);
        continue;
      }
      const bool is_a = out.model_id == 1u && out.mpe_um == ya[0] && out.rpe_um == ya[1] &&
                        out.mae_um == ya[2] && out.rae_um == ya[3];
      const bool is_b = out.model_id == 2u && out.mpe_um == yb[0] && out.rpe_um == yb[1] &&
                        out.mae_um == yb[2] && out.rae_um == yb[3];
      if (!is_a && !is_b) mixed.fetch_add(1);
      (is_a ? seen_a : seen_b).fetch_add(1, std::memory_order_relaxed);
      calls.fetch_add(1, std::memory_order_relaxed);
    }
  });
  // The test waits for what it needs, never for luck: the swaps start once the reader is
  // demonstrably running, and go on until it has read across many of them and seen both models
  // (on a loaded 2-core machine the writer could otherwise finish before the reader ran).
  while (calls.load(std::memory_order_relaxed) == 0) std::this_thread::yield();
  std::uint64_t publishes = 0;
  while (publishes < 1000 || calls.load(std::memory_order_relaxed) < 2000 ||
         seen_a.load(std::memory_order_relaxed) == 0 ||
         seen_b.load(std::memory_order_relaxed) == 0) {
    const bool even = publishes % 2 == 0;
    ASSERT_EQ(comp.publish(0, even ? b : a, even ? 2u : 1u), Status::kOk);
    if (++publishes % 50 == 0) std::this_thread::yield();
  }
  done.store(true, std::memory_order_release);
  reader.join();
  EXPECT_EQ(mixed.load(), 0u);
  EXPECT_GE(calls.load(), 2000u);
  EXPECT_GT(seen_a.load(), 0u);
  EXPECT_GT(seen_b.load(), 0u);
  std::printf("hot swap: %llu calls, %llu from model A, %llu from model B\n",
              static_cast<unsigned long long>(calls.load()),
              static_cast<unsigned long long>(seen_a.load()),
              static_cast<unsigned long long>(seen_b.load()));
}

}  // namespace
}  // namespace cmmcomp::compensation

namespace cmmcomp::compensation {
namespace {

IntervalCalibration test_interval() {
  IntervalCalibration cal;
  cal.coverage = 0.95;
  cal.half_width = {2.0, 1.5, 1.0, 0.5};
  cal.extrapolation_gain = {0.0, 1.0, 2.0, 0.25};
  return cal;
}

// docs/uncertainty.md: U = h·(1 + g·d), d the distance from the training box in training ranges.
TEST(MoveCompensatorInterval, InsideTheDomainU95IsTheHalfWidth) {
  MoveCompensator comp;
  const IntervalCalibration cal = test_interval();
  ASSERT_EQ(comp.publish(0, linear_model({3.0, -1.25, 4.0, 2.5}, {1.0, 0.5, 0.0, 2.0}), cal, 5u),
            Status::kOk);
  Correction out;
  ASSERT_EQ(comp.before_approach(move_at(42.5), out), Status::kOk);
  EXPECT_EQ(out.flags, kFlagOk);  // calibrated: no kFlagNoUncertainty
  for (std::size_t o = 0; o < 4; ++o) EXPECT_EQ(out.u95_um[o], cal.half_width[o]) << o;
  EXPECT_NEAR(out.rae_um, 3.5, 1e-12);  // the prediction itself does not change
}

TEST(MoveCompensatorInterval, GrowsOutsideTheDomainUnderEitherPolicy) {
  const Model m = linear_model({0, 0, 0, 1.0}, {0, 0, 0, 2.0});
  const IntervalCalibration cal = test_interval();
  // PV 86 against the range [5, 80]: d = (86 − 80)/75 = 0.08 (not far outside: below 0.1).
  const double d = 6.0 / 75.0;
  for (const auto policy : {fuzzy::DomainPolicy::kClamp, fuzzy::DomainPolicy::kExtrapolate}) {
    CompensatorOptions o;
    o.outside_domain = policy;
    MoveCompensator comp{o};
    ASSERT_EQ(comp.publish(0, m, cal), Status::kOk);
    Correction out;
    ASSERT_EQ(comp.before_approach(move_at(86.0), out), Status::kOutsideDomain);
    EXPECT_EQ(out.flags, kFlagOk | kFlagOutsideDomain);
    for (std::size_t k = 0; k < 4; ++k) {
      EXPECT_NEAR(out.u95_um[k], cal.half_width[k] * (1.0 + cal.extrapolation_gain[k] * d), 1e-12)
          << "output " << k;
    }
    EXPECT_GT(out.u95_um[3], cal.half_width[3]);
  }
}

// Any finite input gives a finite interval: the distance counts each input's excess up to
// kMaxRangesOutside ranges, the half-width is bounded by kMaxHalfWidth (a 1e200 input used to
// overflow the distance to inf, and 0 · inf gave NaN where a gain is 0).
TEST(MoveCompensatorInterval, FarOutsideTheDomainTheIntervalStaysFinite) {
  const std::array<fuzzy::InputRange, 2> ranges{{{5.0, 80.0}, {-1.0, 1.0}}};
  for (const double x : {1e200, -1e300, std::numeric_limits<double>::max()}) {
    const double d = fuzzy::domain_distance(ranges, std::array<double, 2>{x, x});
    EXPECT_TRUE(std::isfinite(d)) << x;
    EXPECT_NEAR(d, std::sqrt(2.0) * fuzzy::kMaxRangesOutside, 1e-6 * fuzzy::kMaxRangesOutside);
    IntervalCalibration cal = test_interval();
    cal.extrapolation_gain[1] = 1e300;
    std::array<double, 4> u{};
    fuzzy::interval_half_widths(cal, d, 1.0, u);
    for (std::size_t o = 0; o < 4; ++o) {
      EXPECT_TRUE(std::isfinite(u[o])) << o;
      EXPECT_LE(u[o], fuzzy::kMaxHalfWidth) << o;
    }
    EXPECT_EQ(u[0], cal.half_width[0]);  // gain 0: the in-domain half-width, not NaN
    EXPECT_EQ(u[1], fuzzy::kMaxHalfWidth);
  }
}

// κ = (mean (2u − 1)²)²: 0 at the centre, 1 at a corner and beyond; U = h·(1 + k·κ + g·d).
TEST(MoveCompensatorInterval, CornerShareAndCornerGain) {
  const std::array<fuzzy::InputRange, 2> ranges{{{5.0, 80.0}, {-1.0, 1.0}}};
  using X = std::array<double, 2>;
  EXPECT_EQ(fuzzy::corner_share(ranges, X{42.5, 0.0}), 0.0);
  EXPECT_EQ(fuzzy::corner_share(ranges, X{5.0, 1.0}), 1.0);
  EXPECT_EQ(fuzzy::corner_share(ranges, X{1e300, -1e300}), 1.0);  // clamped: beyond is d's part
  // One input at its end, the other at the centre: mean 0.5, κ = 0.25.
  EXPECT_DOUBLE_EQ(fuzzy::corner_share(ranges, X{80.0, 0.0}), 0.25);
  // Half-way to the end on both: (2u − 1)² = 0.25, κ = 0.25².
  EXPECT_DOUBLE_EQ(fuzzy::corner_share(ranges, X{61.25, 0.5}), 0.0625);

  IntervalCalibration cal = test_interval();
  cal.corner_gain = {0.0, 2.0, 0.5, 1.0};
  std::array<double, 4> u{};
  fuzzy::interval_half_widths_at(cal, ranges, X{5.0, -1.0}, u);  // a corner, d = 0
  for (std::size_t o = 0; o < 4; ++o) {
    EXPECT_DOUBLE_EQ(u[o], cal.half_width[o] * (1.0 + cal.corner_gain[o])) << o;
  }
  fuzzy::interval_half_widths_at(cal, ranges, X{42.5, 0.0}, u);  // the centre
  for (std::size_t o = 0; o < 4; ++o) EXPECT_DOUBLE_EQ(u[o], cal.half_width[o]) << o;
  // Both terms add beyond a corner: PV 155 is 1 range out, κ = 1.
  fuzzy::interval_half_widths_at(cal, ranges, X{155.0, 1.0}, u);
  for (std::size_t o = 0; o < 4; ++o) {
    EXPECT_DOUBLE_EQ(u[o],
                     cal.half_width[o] * (1.0 + cal.corner_gain[o] + cal.extrapolation_gain[o]))
        << o;
  }
  IntervalCalibration bad = test_interval();
  bad.corner_gain[2] = -0.5;
  std::string why;
  EXPECT_FALSE(fuzzy::validate_interval(bad, &why));
  EXPECT_NE(why.find("corner gain of output 2"), std::string::npos) << why;
  EXPECT_FALSE(fuzzy::interval_is_valid(bad));
}

TEST(MoveCompensatorInterval, AnInvalidCalibrationIsRefusedAndTheOldModelServes) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, linear_model({0, 0, 0, 1.0}, {0, 0, 0, 0}), test_interval(), 1u),
            Status::kOk);
  for (const double bad : {std::nan(""), -1.0, std::numeric_limits<double>::infinity()}) {
    IntervalCalibration cal = test_interval();
    cal.half_width[2] = bad;
    std::string why;
    EXPECT_EQ(comp.publish(0, linear_model({0, 0, 0, 9.0}, {0, 0, 0, 0}), cal, 2u, &why),
              Status::kInvalidInput);
    EXPECT_NE(why.find("half-width of output 2"), std::string::npos) << why;
  }
  IntervalCalibration no_coverage = test_interval();
  no_coverage.coverage = 0.0;  // values without a coverage: a corrupt calibration, not "none"
  EXPECT_EQ(comp.publish(0, linear_model({0, 0, 0, 9.0}, {0, 0, 0, 0}), no_coverage, 3u),
            Status::kInvalidInput);
  Correction out;
  ASSERT_EQ(comp.before_approach(move_at(40.0), out), Status::kOk);
  EXPECT_EQ(out.model_id, 1u);
  EXPECT_NEAR(out.rae_um, 1.0, 1e-12);
  EXPECT_EQ(out.u95_um[3], 0.5);
}

// The calibration travels with its model: a hot swap to an uncalibrated model drops it.
TEST(MoveCompensatorInterval, IsPublishedWithItsModel) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, linear_model({0, 0, 0, 1.0}, {0, 0, 0, 0}), test_interval(), 1u),
            Status::kOk);
  ASSERT_EQ(comp.publish(0, linear_model({0, 0, 0, 2.0}, {0, 0, 0, 0}), 2u), Status::kOk);
  Correction out;
  ASSERT_EQ(comp.before_approach(move_at(40.0), out), Status::kOk);
  EXPECT_EQ(out.flags, kFlagOk | kFlagNoUncertainty);
  for (const double u : out.u95_um) EXPECT_EQ(u, 0.0);
  // Axis 1 never had a model.
  MoveRequest other = move_at(40.0);
  other.axis = 1;
  EXPECT_EQ(comp.before_approach(other, out), Status::kNoModel);
}

}  // namespace
}  // namespace cmmcomp::compensation
