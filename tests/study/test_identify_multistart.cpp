// SPDX-License-Identifier: MIT
/// @file study::identify_multistart and study::paper_calibration (cmmcomp/study/): the starts
/// are the start machine and its free parameters scaled within 2^±spread, reproducibly; each
/// fit is judged; bad plans are ConfigErrors.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/calibration.hpp>
#include <cmmcomp/study/identify_multistart.hpp>
#include <string>

namespace cmmcomp::study {
namespace {

PaperIdentification quick() {
  PaperIdentification p = paper_identification(std::string(CMMCOMP_SOURCE_DIR) + "/data/paper");
  p.options.free_parameters = {"structure.mode_frequency_hz", "hose.coulomb_drag_N"};
  p.options.max_iterations = 1;
  return p;
}

TEST(StudyIdentifyMultistart, StartsAreTheMachineAndItsScaledCopies) {
  const PaperIdentification p = quick();
  MultistartPlan plan;
  plan.starts = 3;
  plan.spread = 0.5;
  plan.calibration_seeds = 1;
  const dynamics::Machine start = dynamics::default_machine();
  const MultistartResult r = identify_multistart(start, p.targets, p.options, plan);
  ASSERT_EQ(r.rows.size(), 3u);
  const double f0 = start.parameters.mode_frequency_hz;
  EXPECT_EQ(r.rows[0].start_values[0], f0);
  for (std::size_t i = 1; i < 3; ++i) {
    const double ratio = r.rows[i].start_values[0] / f0;
    EXPECT_GE(ratio, std::exp2(-0.5));
    EXPECT_LE(ratio, std::exp2(0.5));
    EXPECT_NE(ratio, 1.0);
  }
  for (const MultistartRow& row : r.rows) {
    if (!row.failure.empty()) continue;
    EXPECT_EQ(row.fitted_values.size(), 2u);
    EXPECT_GT(row.requirements, 0);
    EXPECT_LE(row.held, row.requirements);
    EXPECT_LE(row.final_cost, row.initial_cost);
  }
  // The same plan draws the same starts.
  const MultistartResult again = identify_multistart(start, p.targets, p.options, plan);
  EXPECT_EQ(again.rows[2].start_values, r.rows[2].start_values);
}

TEST(StudyIdentifyMultistart, ABadPlanIsAConfigError) {
  const PaperIdentification p = quick();
  MultistartPlan plan;
  plan.starts = 0;
  EXPECT_THROW(identify_multistart(dynamics::default_machine(), p.targets, p.options, plan),
               ConfigError);
  plan.starts = 1;
  PaperIdentification none = p;
  none.options.free_parameters.clear();
  EXPECT_THROW(identify_multistart(dynamics::default_machine(), none.targets, none.options, plan),
               ConfigError);
  none.options.free_parameters = {"structure.no_such_key"};
  EXPECT_THROW(identify_multistart(dynamics::default_machine(), none.targets, none.options, plan),
               ConfigError);
}

TEST(StudyCalibration, OneTargetPerRequirementHeldOverTheSeeds) {
  const CalibrationResult c = paper_calibration(dynamics::default_machine(), 1, 3);
  EXPECT_EQ(c.needed, 3);  // fewer than 50 seeds: every one
  ASSERT_EQ(c.targets.size(), c.first.checks.size());
  for (std::size_t i = 0; i < c.targets.size(); ++i) {
    EXPECT_EQ(c.targets[i].name, c.first.checks[i].requirement);
    EXPECT_GE(c.targets[i].measured, 0);
    EXPECT_LE(c.targets[i].measured, 3);
    // A requirement that failed at the first seed cannot have held for every seed.
    if (!c.first.checks[i].passed) {
      EXPECT_FALSE(c.targets[i].met());
    }
  }
  EXPECT_EQ(paper_calibration(dynamics::default_machine(), 1, 100).needed, 98);
  EXPECT_THROW(paper_calibration(dynamics::default_machine(), 1, 0), ConfigError);
}

}  // namespace
}  // namespace cmmcomp::study
