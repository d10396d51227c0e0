// SPDX-License-Identifier: MIT
/// @file MoveCompensator::before_approach never allocates, on success and on every error path;
/// StaticMoveCompensator (firmware) allocates in neither before_approach nor publish.
#include <gtest/gtest.h>

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstdint>
#include <limits>
#include <vector>

#include "support/allocation_counter.hpp"
#include "support/compensation_models.hpp"

namespace cmmcomp::compensation {
namespace {

// Output o = (o + 1) + 0.25·o·x̂_PD everywhere.
Model<PaperInputs> flat_model() {
  return test::linear_model({1.0, 2.0, 3.0, 4.0}, {0.0, 0.25, 0.5, 0.75}, 2);
}

MoveRequest move(int i) {
  MoveRequest r;
  r.sequence = static_cast<std::uint32_t>(i);
  r.axis = static_cast<std::uint8_t>(i % 2);
  r.pv_mm_s = 5.0 + (i % 82);  // some outside [5, 80], none far outside (beyond 87.5)
  r.pa_mm_s2 = 500.0;
  r.pd_mm = 1.0 + (i % 49);
  r.av_mm_s = 2.0;
  r.aa_mm_s2 = 100.0;
  r.ad_mm = 1.0;
  return r;
}

TEST(MoveCompensatorRt, BeforeApproachDoesNotAllocate) {
  MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, flat_model()), Status::kOk);  // allocation allowed here
  ASSERT_EQ(comp.publish(1, flat_model()), Status::kOk);
  Correction out;
  std::size_t failures = 0;
  test::AllocationCounter allocs;
  for (int i = 0; i < 10000; ++i) failures += ok(comp.before_approach(move(i), out)) ? 0 : 1;
  MoveRequest bad = move(0);
  bad.pv_mm_s = std::numeric_limits<double>::quiet_NaN();
  failures += comp.before_approach(bad, out) == Status::kInvalidInput ? 0 : 1;
  bad = move(0);
  bad.axis = 3;  // no model
  failures += comp.before_approach(bad, out) == Status::kNoModel ? 0 : 1;
  bad = move(0);
  bad.pv_mm_s = 1e6;  // far outside: refused under every policy
  failures += comp.before_approach(bad, out) == Status::kOutsideDomainRejected ? 0 : 1;
  EXPECT_EQ(allocs.count(), 0u);
  EXPECT_EQ(failures, 0u);
}

StaticMoveCompensator<Model<PaperInputs>> g_static;

TEST(StaticMoveCompensatorRt, NeitherPublishNorBeforeApproachAllocates) {
  const Model<PaperInputs> good = flat_model();
  Model<PaperInputs> bad = good;
  bad.params.width(0, 0) = -1.0;
  Correction out;
  std::size_t failures = 0;
  test::AllocationCounter allocs;
  failures += g_static.publish(0, good, 1) == Status::kOk ? 0 : 1;
  failures += g_static.publish(1, good, 1) == Status::kOk ? 0 : 1;
  failures += g_static.publish(1, bad, 2) == Status::kInvalidInput ? 0 : 1;
  for (int i = 0; i < 10000; ++i) failures += ok(g_static.before_approach(move(i), out)) ? 0 : 1;
  MoveRequest bad_move = move(0);
  bad_move.axis = 3;  // no model
  failures += g_static.before_approach(bad_move, out) == Status::kNoModel ? 0 : 1;
  bad_move = move(0);
  bad_move.pv_mm_s = 1e6;  // far outside
  failures += g_static.before_approach(bad_move, out) == Status::kOutsideDomainRejected ? 0 : 1;
  EXPECT_EQ(allocs.count(), 0u);
  EXPECT_EQ(failures, 0u);
}

TEST(MoveCompensatorRt, CounterSeesAnAllocation) {  // the positive control
  test::AllocationCounter allocs;
  std::vector<double> v(10, 1.0);
  asm volatile("" : : "g"(v.data()) : "memory");
  EXPECT_EQ(allocs.count(), 1u);
}

}  // namespace
}  // namespace cmmcomp::compensation
