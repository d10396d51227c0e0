// SPDX-License-Identifier: MIT
/// @file The model's domain (compensation/conditions.hpp, docs/compensator.md "Domain"): a move
/// whose PA or AA lies outside the training conditions is flagged or refused; a move far outside
/// the box or the conditions is refused under every policy; the same in MoveCompensator and
/// StaticMoveCompensator; and the outcome log's ring.
#include <gtest/gtest.h>

#include <atomic>
#include <cmmcomp/compensation/conditions.hpp>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstdint>
#include <limits>
#include <string>
#include <thread>

#include "support/compensation_models.hpp"

namespace cmmcomp::compensation {
namespace {

using Model = compensation::Model<PaperInputs>;
using test::linear_model;

constexpr auto kPolicies = {
    fuzzy::DomainPolicy::kClamp, fuzzy::DomainPolicy::kExtrapolate, fuzzy::DomainPolicy::kReject};

// Inside the linear model's box ([5, 80], [1, 50], [1, 10], [0.5, 5]).
MoveRequest inside(double pa = 200.0, double aa = 60.0) {
  MoveRequest r;
  r.sequence = 3;
  r.direction = {-1.0, 0.0, 0.0};
  r.pv_mm_s = 40.0;
  r.pa_mm_s2 = pa;
  r.pd_mm = 20.0;
  r.av_mm_s = 5.0;
  r.aa_mm_s2 = aa;
  r.ad_mm = 2.0;
  return r;
}

Conditions trained_at_200_60() {
  Conditions c;
  c.pa_mm_s2 = {200.0, 200.0};
  c.aa_mm_s2 = {40.0, 80.0};
  return c;
}

TEST(Conditions, DomainOfOneValueAndOfARange) {
  const Conditions c = trained_at_200_60();
  // PA trained at one value: 1 % of the value counts as inside, 10 % of it is the far limit.
  EXPECT_EQ(condition_domain(c, inside(200.0)), Domain::kInside);
  EXPECT_EQ(condition_domain(c, inside(201.9)), Domain::kInside);
  EXPECT_EQ(condition_domain(c, inside(198.1)), Domain::kInside);
  EXPECT_EQ(condition_domain(c, inside(205.0)), Domain::kOutside);
  EXPECT_EQ(condition_domain(c, inside(190.0)), Domain::kOutside);
  EXPECT_EQ(condition_domain(c, inside(219.0)), Domain::kOutside);
  EXPECT_EQ(condition_domain(c, inside(221.0)), Domain::kFarOutside);
  EXPECT_EQ(condition_domain(c, inside(1200.0)), Domain::kFarOutside);
  EXPECT_EQ(condition_domain(c, inside(100.0)), Domain::kFarOutside);
  // AA over a range [40, 80]: the far limit is 10 % of its width, 4 mm/s².
  EXPECT_EQ(condition_domain(c, inside(200.0, 40.0)), Domain::kInside);
  EXPECT_EQ(condition_domain(c, inside(200.0, 80.0)), Domain::kInside);
  EXPECT_EQ(condition_domain(c, inside(200.0, 83.0)), Domain::kOutside);
  EXPECT_EQ(condition_domain(c, inside(200.0, 85.0)), Domain::kFarOutside);
  EXPECT_EQ(condition_domain(c, inside(200.0, 35.0)), Domain::kFarOutside);
  // Unknown conditions are not checked.
  EXPECT_EQ(condition_domain(Conditions{}, inside(1e6, 1e6)), Domain::kInside);
}

TEST(Conditions, ValidityOfTheRanges) {
  EXPECT_TRUE(conditions_are_valid(Conditions{}));
  EXPECT_TRUE(conditions_are_valid(trained_at_200_60()));
  Conditions c;
  c.pa_mm_s2 = {300.0, 200.0};
  EXPECT_FALSE(conditions_are_valid(c));
  c.pa_mm_s2 = {0.0, 200.0};
  EXPECT_FALSE(conditions_are_valid(c));
  c.pa_mm_s2 = {-1.0, -1.0};
  EXPECT_FALSE(conditions_are_valid(c));
  c.pa_mm_s2 = {100.0, std::numeric_limits<double>::infinity()};
  EXPECT_FALSE(conditions_are_valid(c));
  c.pa_mm_s2 = {std::numeric_limits<double>::quiet_NaN(), 100.0};
  EXPECT_FALSE(conditions_are_valid(c));
}

TEST(Conditions, InputsFarOutsideTheBox) {
  const Model m = linear_model({0, 0, 0, 1.0}, {0, 0, 0, 2.0});
  MoveRequest r = inside();
  EXPECT_EQ(input_domain(m, r), Domain::kInside);
  r.pv_mm_s = 80.0;  // the range's end
  EXPECT_EQ(input_domain(m, r), Domain::kInside);
  r.pv_mm_s = 87.0;  // 7 of 75 beyond: outside, not far
  EXPECT_EQ(input_domain(m, r), Domain::kOutside);
  r.pv_mm_s = 88.0;  // 8 of 75 beyond: far (more than 7.5)
  EXPECT_EQ(input_domain(m, r), Domain::kFarOutside);
  r.pv_mm_s = 1e6;
  EXPECT_EQ(input_domain(m, r), Domain::kFarOutside);
}

// Every policy: the table of docs/compensator.md, "Domain".
TEST(Conditions, MoveCompensatorAppliesTheRuleUnderEveryPolicy) {
  const Model m = linear_model({0, 0, 0, 1.0}, {0, 0, 0, 2.0});
  for (const auto policy : kPolicies) {
    CompensatorOptions o;
    o.outside_domain = policy;
    MoveCompensator comp(o);
    ASSERT_EQ(comp.publish(0, m, IntervalCalibration{}, trained_at_200_60(), 9), Status::kOk);
    const bool reject = policy == fuzzy::DomainPolicy::kReject;
    Correction out;
    EXPECT_EQ(comp.before_approach(inside(), out), Status::kOk);
    EXPECT_EQ(out.flags & kFlagOutsideDomain, 0u);
    // PA outside the conditions, inputs inside: flagged (the answer is the in-domain one) or
    // refused.
    Correction at_210;
    const Status s = comp.before_approach(inside(210.0), at_210);
    if (reject) {
      EXPECT_EQ(s, Status::kOutsideDomainRejected);
    } else {
      EXPECT_EQ(s, Status::kOutsideDomain);
      EXPECT_EQ(at_210.flags & (kFlagOk | kFlagOutsideDomain), kFlagOk | kFlagOutsideDomain);
      EXPECT_EQ(at_210.rae_um, out.rae_um);
    }
    // Far outside, in a condition or an input: refused under every policy.
    EXPECT_EQ(comp.before_approach(inside(1200.0), out), Status::kOutsideDomainRejected);
    EXPECT_EQ(comp.before_approach(inside(200.0, 6.0), out), Status::kOutsideDomainRejected);
    MoveRequest fast = inside();
    fast.pv_mm_s = 1e6;
    EXPECT_EQ(comp.before_approach(fast, out), Status::kOutsideDomainRejected);
    fast.pv_mm_s = 85.0;  // outside, not far: the policy decides
    EXPECT_EQ(comp.before_approach(fast, out),
              reject ? Status::kOutsideDomainRejected : Status::kOutsideDomain);
  }
}

TEST(Conditions, StaticCompensatorAppliesTheSameRule) {
  const Model m = linear_model({0, 0, 0, 1.0}, {0, 0, 0, 2.0});
  for (const auto policy : kPolicies) {
    StaticMoveCompensator<Model> fw(policy);
    CompensatorOptions o;
    o.outside_domain = policy;
    MoveCompensator host(o);
    ASSERT_EQ(fw.publish(0, m, IntervalCalibration{}, trained_at_200_60(), 9), Status::kOk);
    ASSERT_EQ(host.publish(0, m, IntervalCalibration{}, trained_at_200_60(), 9), Status::kOk);
    for (const double pa : {200.0, 201.0, 210.0, 230.0, 1200.0, 150.0}) {
      for (const double pv : {40.0, 85.0, 90.0, 1e6}) {
        MoveRequest r = inside(pa);
        r.pv_mm_s = pv;
        Correction a;
        Correction b;
        const Status sa = fw.before_approach(r, a);
        EXPECT_EQ(sa, host.before_approach(r, b)) << "PA " << pa << " PV " << pv;
        if (ok(sa)) {
          EXPECT_EQ(a.flags, b.flags);
          EXPECT_EQ(a.rae_um, b.rae_um);
        }
      }
    }
  }
}

TEST(Conditions, InvalidConditionsAreRefusedAndTheOldModelServes) {
  const Model m = linear_model({0, 0, 0, 1.0}, {0, 0, 0, 2.0});
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, m, IntervalCalibration{}, trained_at_200_60(), 1), Status::kOk);
  Conditions bad;
  bad.aa_mm_s2 = {80.0, 40.0};
  std::string why;
  EXPECT_EQ(comp.publish(0, m, IntervalCalibration{}, bad, 2, &why), Status::kInvalidInput);
  EXPECT_NE(why.find("AA"), std::string::npos) << why;
  EXPECT_EQ(comp.model_id(0), 1u);
  Correction out;
  EXPECT_EQ(comp.before_approach(inside(1200.0), out), Status::kOutsideDomainRejected);

  StaticMoveCompensator<Model> fw;
  EXPECT_EQ(fw.publish(0, m, IntervalCalibration{}, bad, 2), Status::kInvalidInput);
  EXPECT_FALSE(fw.has_model(0));
}

TEST(OutcomeLog, KeepsOrderAndCountsWhatItDrops) {
  OutcomeLog<4> log;
  OutcomeEvent e;
  EXPECT_FALSE(log.pop(e));
  for (std::uint32_t k = 0; k < 6; ++k) {
    OutcomeEvent in;
    in.move.sequence = k;
    in.status = Status::kOutsideDomain;
    log.push(in);
  }
  EXPECT_EQ(log.dropped(), 2u);
  for (std::uint32_t k = 0; k < 4; ++k) {
    ASSERT_TRUE(log.pop(e));
    EXPECT_EQ(e.move.sequence, k);
  }
  EXPECT_FALSE(log.pop(e));
  OutcomeEvent again;
  again.move.sequence = 42;
  log.push(again);
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.move.sequence, 42u);
  EXPECT_TRUE(worth_logging(Status::kOutsideDomain));
  EXPECT_TRUE(worth_logging(Status::kOutsideDomainRejected));
  EXPECT_FALSE(worth_logging(Status::kOk));
}

// One producer, one consumer: every event arrives once and in order, or is counted as dropped.
TEST(OutcomeLog, OneProducerOneConsumer) {
  static OutcomeLog<64> log;
  constexpr std::uint32_t kEvents = 200000;
  std::atomic<bool> done{false};
  std::thread producer([&] {
    for (std::uint32_t k = 0; k < kEvents; ++k) {
      OutcomeEvent e;
      e.move.sequence = k;
      e.move.pv_mm_s = k;
      e.status = Status::kOutsideDomainRejected;
      log.push(e);
    }
    done = true;
  });
  std::uint64_t received = 0;
  std::int64_t last = -1;
  bool ordered = true;
  OutcomeEvent e;
  while (true) {
    const bool finished = done.load();
    while (log.pop(e)) {
      ordered = ordered && static_cast<std::int64_t>(e.move.sequence) > last &&
                e.move.pv_mm_s == e.move.sequence;
      last = e.move.sequence;
      ++received;
    }
    if (finished) break;
  }
  producer.join();
  EXPECT_TRUE(ordered);
  EXPECT_EQ(received + log.dropped(), kEvents);
}

}  // namespace
}  // namespace cmmcomp::compensation
