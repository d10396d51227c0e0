// SPDX-License-Identifier: MIT
/// @file The measurement plan: randomised run order in blocks, the coordinates, plan.csv and the
/// I++ program read back value by value (docs/measurement.md).
#include <gtest/gtest.h>

#include <cctype>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/doe/levels.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/ipp_number.hpp>
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
    // Every number at the I++ resolution (1e-6, io/ipp_number.hpp): within half of it.
    constexpr double kHalf = 0.5e-6 * (1 + 1e-9);
    EXPECT_NEAR(p.goto_speed, m.settings.pv_mm_s, kHalf);
    EXPECT_NEAR(p.goto_accel, m.settings.pa_mm_s2, kHalf);
    EXPECT_NEAR(p.meas_speed, m.settings.av_mm_s, kHalf);
    EXPECT_NEAR(p.meas_accel, m.settings.aa_mm_s2, kHalf);
    EXPECT_NEAR(p.approach, m.settings.ad_mm, kHalf) << "I++ Approach: from the point along IJK";
    EXPECT_EQ(p.search, o.search_mm);
    EXPECT_EQ(p.retract, o.retract_mm);
    ASSERT_EQ(p.gotos.size(), 2u);
    EXPECT_NEAR(p.gotos[0].x, m.start.x, kHalf);
    EXPECT_NEAR(p.gotos[1].x, m.prehit.x, kHalf);
    EXPECT_NEAR(p.gotos[1].y, m.prehit.y, kHalf);
    EXPECT_NEAR(p.gotos[1].z, m.prehit.z, kHalf);
    EXPECT_NEAR(p.point.x, m.touch.x, kHalf);
    EXPECT_NEAR(p.point.y, m.touch.y, kHalf);
    EXPECT_NEAR(p.point.z, m.touch.z, kHalf);
    EXPECT_EQ(p.ijk.x, 1.0);
    // The pre-hit point is where I++ starts the approach: nominal + Approach · IJK.
    EXPECT_NEAR(p.point.x + p.approach * p.ijk.x, p.gotos[1].x, 3 * kHalf);
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
  // A number no I++ parser reads (issue 39 §1: what plan.ipp wrote before).
  bad = program;
  const std::size_t x = bad.find("GoTo(X(") + 7;
  bad.replace(x, bad.find(')', x) - x, "5.700000000000003");
  try {
    parse_ipp_program(bad, "plan.ipp");
    FAIL();
  } catch (const ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find("plan.ipp:4: a number longer than 16 characters"),
              std::string::npos)
        << e.what();
  }
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

TEST(MeasurePlan, EveryIppNumberHasAtMost16CharactersWhateverTheNominalAndNormal) {
  // Fractional nominals and levels make sums like 5.700000000000003 (17 characters), which I++
  // DME parsers refuse: every number of plan.ipp is at most 16 characters, over random nominal
  // points, normals along every axis and fractional levels, and reads back within 0.5e-6.
  detail::SplitMix64 rng{39};
  std::size_t numbers = 0;
  for (int trial = 0; trial < 60; ++trial) {
    PlanOptions o = l18x3();
    o.repeats = 1;
    o.nominal = {rng.uniform(-2000.0, 2000.0), rng.uniform(0.0, 500.0), rng.uniform(-800.0, 800.0)};
    const int axis = static_cast<int>(rng.below(3));
    const double sign = rng.uniform() < 0.5 ? -1.0 : 1.0;
    o.normal = {axis == 0 ? sign : 0.0, axis == 1 ? sign : 0.0, axis == 2 ? sign : 0.0};
    o.levels = "pv=40.1,70.3,100.7;pd=40.3,60.1,80.9;av=8.1,12.3,16.7;ad=5.1,10.3,14.9";
    o.fixed.y_mm = o.nominal.y;
    o.search_mm = rng.uniform(0.5, 5.0);
    o.retract_mm = rng.uniform(0.5, 5.0);
    std::vector<PlannedMove> moves;
    try {
      moves = plan_experiment(o);
    } catch (const ConfigError& e) {
      ADD_FAILURE() << e.what();
      continue;
    }
    const std::string program = format_ipp_program(moves, o);
    // Every token between '(' or ',' and ',' or ')' that starts like a number.
    std::size_t i = 0;
    while ((i = program.find_first_of("(,", i)) != std::string::npos) {
      std::size_t b = program.find_first_not_of(' ', i + 1);
      const std::size_t e = program.find_first_of(",)", b);
      if (b == std::string::npos || e == std::string::npos) break;
      const std::string token = program.substr(b, e - b);
      if (!token.empty() &&
          (std::isdigit(static_cast<unsigned char>(token[0])) != 0 || token[0] == '-')) {
        ++numbers;
        EXPECT_LE(token.size(), 16u) << token;
        EXPECT_EQ(token.find_first_of("eE"), std::string::npos) << token;
        if (token.find('.') != std::string::npos) {
          EXPECT_NE(token.back(), '0') << token;
        }
      }
      i = b;
    }
    const std::vector<IppPoint> points = parse_ipp_program(program, "plan.ipp");
    ASSERT_EQ(points.size(), moves.size());
    for (std::size_t k = 0; k < moves.size(); ++k) {
      EXPECT_NEAR(points[k].point.x, moves[k].touch.x, 0.5e-6 * (1 + 1e-9));
      EXPECT_NEAR(points[k].point.y, moves[k].touch.y, 0.5e-6 * (1 + 1e-9));
      EXPECT_NEAR(points[k].point.z, moves[k].touch.z, 0.5e-6 * (1 + 1e-9));
    }
  }
  EXPECT_GT(numbers, 60u * 18u * 10u);
}

TEST(MeasurePlan, AnIppNumberIsFixedPointAtMost16Characters) {
  EXPECT_EQ(io::format_ipp_number(5.700000000000003), "5.7");
  EXPECT_EQ(io::format_ipp_number(-0.0000001), "0");
  EXPECT_EQ(io::format_ipp_number(-12.5000004), "-12.5");
  EXPECT_EQ(io::format_ipp_number(100.0), "100");
  EXPECT_EQ(io::format_ipp_number(1e-6), "0.000001");
  EXPECT_EQ(io::format_ipp_number(123456789.1234567), "123456789.123457");
  EXPECT_EQ(io::format_ipp_number(-123456789.1234567), "-123456789.12346");
  EXPECT_EQ(io::format_ipp_number(1234567890123456.0), "1234567890123456");
  EXPECT_THROW(io::format_ipp_number(1e17), ConfigError);
  EXPECT_THROW(io::format_ipp_number(std::nan("")), ConfigError);
  EXPECT_THROW(io::format_ipp_number(-HUGE_VAL), ConfigError);
}

}  // namespace cmmcomp::measure
