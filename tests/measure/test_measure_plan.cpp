// SPDX-License-Identifier: MIT
/// @file The measurement plan: randomised run order in blocks, the coordinates, plan.csv and the
/// I++ program read back value by value (docs/measurement.md).
#include <gtest/gtest.h>

#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <fstream>
#include <set>
#include <sstream>
#include <string>

namespace cmmcomp::measure {
namespace {

PlanOptions l18x3() {
  PlanOptions o;
  o.nominal = {100.0, 0.0, -50.0};
  o.normal = {1.0, 0.0, 0.0};
  return o;
}

TEST(MeasurePlan, EveryRunOncePerBlockInRandomOrderNeverBackToBack) {
  const std::vector<PlannedMove> moves = plan_experiment(l18x3());
  ASSERT_EQ(moves.size(), 54u);
  std::set<std::pair<int, int>> seen;
  for (std::size_t i = 0; i < moves.size(); ++i) {
    EXPECT_EQ(moves[i].run_order, static_cast<int>(i) + 1);
    EXPECT_EQ(moves[i].move_id, (moves[i].run - 1) * 3 + moves[i].repeat);
    EXPECT_TRUE(seen.emplace(moves[i].run, moves[i].repeat).second);
    EXPECT_EQ(moves[i].repeat, static_cast<int>(i) / 18 + 1) << "block = repeat";
    if (i > 0) {
      EXPECT_NE(moves[i].run, moves[i - 1].run) << "a run repeated back to back at " << i;
    }
  }
  // Randomised: not the design order, and another seed gives another order.
  int in_design_order = 0;
  for (std::size_t i = 0; i < 18; ++i) in_design_order += moves[i].run == static_cast<int>(i) + 1;
  EXPECT_LT(in_design_order, 6);
  PlanOptions other = l18x3();
  other.seed = 2;
  const std::vector<PlannedMove> b = plan_experiment(other);
  int same = 0;
  for (std::size_t i = 0; i < moves.size(); ++i) same += moves[i].run == b[i].run;
  EXPECT_LT(same, 20);
  // Seeded: the same seed, the same plan.
  EXPECT_EQ(format_plan_csv(plan_experiment(l18x3())), format_plan_csv(moves));
}

TEST(MeasurePlan, SettingsAreTheDatasetRowsAndCoordinatesFollowTheNormal) {
  const PlanOptions o = l18x3();
  const std::vector<PlannedMove> moves = plan_experiment(o);
  const doe::Design design =
      doe::design_from_text("l18", doe::table3_levels_text(), o.lhs_samples, o.seed);
  const std::vector<DatasetRow> rows = dynamics::rows_from_design(design, o.fixed);
  for (const PlannedMove& m : moves) {
    const DatasetRow& r = rows[static_cast<std::size_t>(m.run - 1)];
    EXPECT_EQ(m.settings.pv_mm_s, r.pv_mm_s);
    EXPECT_EQ(m.settings.pd_mm, r.pd_mm);
    EXPECT_EQ(m.settings.av_mm_s, r.av_mm_s);
    EXPECT_EQ(m.settings.ad_mm, r.ad_mm);
    EXPECT_EQ(m.settings.pa_mm_s2, o.fixed.pa_mm_s2);
    EXPECT_EQ(m.axis, 'x');
    EXPECT_EQ(m.direction, -1) << "the normal points +X: the probe moves in −X";
    EXPECT_EQ(m.touch.x, 100.0);
    EXPECT_EQ(m.touch.y, o.fixed.y_mm) << "the carriage sits where the point is";
    EXPECT_EQ(m.touch.z, -50.0);
    EXPECT_DOUBLE_EQ(m.prehit.x, 100.0 + r.ad_mm);
    EXPECT_DOUBLE_EQ(m.start.x, 100.0 + r.ad_mm + r.pd_mm);
    EXPECT_EQ(m.start.y, m.touch.y);
  }
}

TEST(MeasurePlan, YLevelsSetEachMovesCarriagePosition) {
  PlanOptions o = l18x3();
  o.levels = doe::table3_levels_text() + ";y=0,250,500";
  o.repeats = 1;
  const std::vector<PlannedMove> moves = plan_experiment(o);
  std::set<double> ys;
  for (const PlannedMove& m : moves) {
    ys.insert(m.touch.y);
    EXPECT_EQ(m.touch.y, m.settings.y_mm);
  }
  EXPECT_EQ(ys, (std::set<double>{0.0, 250.0, 500.0}));
  o.normal = {0, -1, 0};
  EXPECT_THROW(plan_experiment(o), ConfigError) << "Y levels and a Y approach";
}

TEST(MeasurePlan, RejectsANormalOffTheAxesAndBadRepeats) {
  PlanOptions o = l18x3();
  o.normal = {0.6, 0.8, 0};
  try {
    plan_experiment(o);
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("machine axis"), std::string::npos) << e.what();
  }
  o = l18x3();
  o.repeats = 0;
  EXPECT_THROW(plan_experiment(o), ConfigError);
  o = l18x3();
  o.design = "l7";
  EXPECT_THROW(plan_experiment(o), ConfigError);
}

TEST(MeasurePlan, PlanCsvRoundTripsExactly) {
  PlanOptions o = l18x3();
  o.normal = {0, 0, -1};
  const std::vector<PlannedMove> moves = plan_experiment(o);
  const std::vector<PlannedMove> back = parse_plan_csv(format_plan_csv(moves), "plan.csv");
  ASSERT_EQ(back.size(), moves.size());
  EXPECT_EQ(format_plan_csv(back), format_plan_csv(moves));
  EXPECT_EQ(back[7].axis, 'z');
  EXPECT_EQ(back[7].direction, 1);
  EXPECT_EQ(back[7].start.z, moves[7].start.z);
}

TEST(MeasurePlan, PlanCsvErrorsNameTheLine) {
  std::string csv = format_plan_csv(plan_experiment(l18x3()));
  const auto third = csv.find('\n', csv.find('\n', csv.find('\n') + 1) + 1);  // after line 3
  csv.insert(third + 1, "1,2,3\n");
  try {
    parse_plan_csv(csv, "plan.csv");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("plan.csv:4:"), std::string::npos) << e.what();
  }
  std::string bad = format_plan_csv(plan_experiment(l18x3()));
  bad.replace(bad.find(",x,"), 3, ",w,");
  EXPECT_THROW(parse_plan_csv(bad, "plan.csv"), ConfigError);
}

TEST(MeasurePlan, TheIppProgramReadsBackToEveryPlannedValue) {
  const PlanOptions o = l18x3();
  const std::vector<PlannedMove> moves = plan_experiment(o);
  const std::string program = format_ipp_program(moves, o);
  EXPECT_EQ(program.rfind("00001 StartSession()\n", 0), 0u);
  const std::vector<IppPoint> points = parse_ipp_program(program, "plan.ipp");
  ASSERT_EQ(points.size(), moves.size());
  for (std::size_t i = 0; i < moves.size(); ++i) {
    const PlannedMove& m = moves[i];
    const IppPoint& p = points[i];
    EXPECT_EQ(p.goto_speed, m.settings.pv_mm_s);
    EXPECT_EQ(p.goto_accel, m.settings.pa_mm_s2);
    EXPECT_EQ(p.meas_speed, m.settings.av_mm_s);
    EXPECT_EQ(p.meas_accel, m.settings.aa_mm_s2);
    EXPECT_EQ(p.approach, m.settings.ad_mm) << "I++ Approach: from the point along IJK = AD";
    EXPECT_EQ(p.search, o.search_mm);
    EXPECT_EQ(p.retract, o.retract_mm);
    ASSERT_EQ(p.gotos.size(), 2u);
    EXPECT_EQ(p.gotos[0].x, m.start.x);
    EXPECT_EQ(p.gotos[1].x, m.prehit.x);
    EXPECT_EQ(p.gotos[1].y, m.prehit.y);
    EXPECT_EQ(p.gotos[1].z, m.prehit.z);
    EXPECT_EQ(p.point.x, m.touch.x);
    EXPECT_EQ(p.point.y, m.touch.y);
    EXPECT_EQ(p.point.z, m.touch.z);
    EXPECT_EQ(p.ijk.x, 1.0);
    // The pre-hit point is where I++ starts the approach: nominal + Approach · IJK.
    EXPECT_DOUBLE_EQ(p.point.x + p.approach * p.ijk.x, p.gotos[1].x);
  }
}

TEST(MeasurePlan, TheIppReaderRejectsWhatItDoesNotKnowWithTheLine) {
  const PlanOptions o = l18x3();
  std::string program = format_ipp_program(plan_experiment(o), o);
  std::string bad = program;
  bad.replace(bad.find("GoTo("), 5, "GoTu(");
  try {
    parse_ipp_program(bad, "plan.ipp");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("plan.ipp:4: unknown command 'GoTu'"), std::string::npos)
        << e.what();
  }
  bad = program;
  bad.replace(bad.find("00003"), 5, "00001");
  EXPECT_THROW(parse_ipp_program(bad, "plan.ipp"), ConfigError) << "tags must increase";
  EXPECT_THROW(parse_ipp_program(program.substr(0, program.rfind("EndSession")), "plan.ipp"),
               ConfigError);
}

}  // namespace
}  // namespace cmmcomp::measure

namespace cmmcomp::measure {
namespace {

std::string measurement_doc() {
  std::ifstream f(std::string(CMMCOMP_DOCS_DIR) + "/measurement.md");
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

/// Every column of a header row the code writes is a `name` in docs/measurement.md.
void expect_documented(const std::string& header, const std::string& doc) {
  std::stringstream cells(header);
  std::string c;
  int n = 0;
  while (std::getline(cells, c, ',')) {
    ++n;
    EXPECT_NE(doc.find("`" + c + "`"), std::string::npos) << c << " is not in docs/measurement.md";
  }
  EXPECT_GT(n, 10);
}

TEST(MeasureDocs, EveryPlanAndReportColumnIsDocumented) {
  const std::string doc = measurement_doc();
  ASSERT_FALSE(doc.empty());
  const std::string plan = format_plan_csv(plan_experiment(PlanOptions{}));
  expect_documented(plan.substr(0, plan.find('\n')), doc);
  const std::string report = format_extraction_report(Extraction{});
  expect_documented(report.substr(0, report.find('\n')), doc);
}

}  // namespace
}  // namespace cmmcomp::measure
