// SPDX-License-Identifier: MIT
/// @file study::qualified_sweep (cmmcomp/study/qualified_sweep.hpp) on a small grid: the
/// settings in grid order, the passes per kind, the fastest of each and their ratio, the
/// targets; and the errors of an empty grid or no seed.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/study/qualified_sweep.hpp>
#include <cmmcomp/study/report.hpp>
#include <string>

namespace cmmcomp::study {
namespace {

io::CompensationModelFile default_y() {
  return io::load_compensation_model(std::string(CMMCOMP_SOURCE_DIR) +
                                     "/data/models/default-y.json");
}

TEST(StudyQualifiedSweep, FindsTheFastestOfEachKindAndTheirRatio) {
  // Two settings: the vc's fast setting, which passes qualified and uncompensated
  // (docs/planner.md, "The qualified reference"), and a shorter approach.
  SweepGrid grid;
  grid.pv_mm_s = {100};
  grid.pd_mm = {60};
  grid.av_mm_s = {16};
  grid.ad_mm = {10, 5};
  const SweepResult r = qualified_sweep(default_y(), dynamics::default_machine(), {1, 2}, grid);
  ASSERT_EQ(r.settings.size(), 2u);
  EXPECT_EQ(r.settings[0].ad_mm, 10.0);
  EXPECT_EQ(r.settings[1].ad_mm, 5.0);
  EXPECT_LT(r.settings[1].time_per_point_s, r.settings[0].time_per_point_s);
  for (const SweepSetting& s : r.settings) {
    EXPECT_GE(s.uncompensated_passes, 0);
    EXPECT_LE(s.uncompensated_passes, 2);
    EXPECT_LE(s.compensated_passes, 2);
  }
  EXPECT_EQ(r.settings[0].uncompensated_passes, 2);
  ASSERT_TRUE(r.fastest_uncompensated.has_value());
  // The fastest of a kind passes every seed, and nothing faster of that kind does.
  for (std::size_t i = 0; i < r.settings.size(); ++i) {
    if (r.settings[i].uncompensated_passes == 2) {
      EXPECT_GE(r.settings[i].time_per_point_s,
                r.settings[*r.fastest_uncompensated].time_per_point_s);
    }
  }
  if (r.fastest_compensated) {
    EXPECT_DOUBLE_EQ(r.speedup,
                     r.settings[*r.fastest_uncompensated].time_per_point_s /
                         r.settings[*r.fastest_compensated].time_per_point_s);
  } else {
    EXPECT_EQ(r.speedup, 0.0);
  }
  ASSERT_EQ(r.targets.size(), 3u);
  EXPECT_TRUE(r.targets[0].met());
  // The document renders (the results page's block).
  Document doc = qualified_sweep_document(r);
  const std::string md = render_markdown(doc);
  EXPECT_NE(md.find("| 100 | 60 | 16 | 10 |"), std::string::npos) << md;
  EXPECT_NE(md.find("Fastest qualified uncompensated setting"), std::string::npos) << md;
}

TEST(StudyQualifiedSweep, AnEmptyGridOrNoSeedIsAConfigError) {
  SweepGrid grid;
  grid.ad_mm.clear();
  EXPECT_THROW(qualified_sweep(default_y(), dynamics::default_machine(), {1}, grid), ConfigError);
  EXPECT_THROW(qualified_sweep(default_y(), dynamics::default_machine(), {}, {}), ConfigError);
}

}  // namespace
}  // namespace cmmcomp::study
