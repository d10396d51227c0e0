// SPDX-License-Identifier: MIT
/// @file The probing-move reconstruction rule: it rebuilds every move of measure's plan.ipp from
/// the program alone, and its cases (own positioning, the 1 µm floor, what it cannot know).
#include <gtest/gtest.h>

#include <cmmcomp/ipp/line.hpp>
#include <cmmcomp/ipp/move_rule.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <sstream>
#include <string>

namespace ipp = cmmcomp::ipp;

namespace {

/// The X(), Y(), Z() and IJK() of a parsed GoTo or PtMeas.
void point_of(const ipp::CommandLine& c, ipp::Point3& p, ipp::Point3& ijk) {
  for (int i = c.args.first(); i >= 0; i = c.args[i].next_sibling) {
    const ipp::Item& it = c.args[i];
    const int k = it.first_child;
    if (it.text == "X") p.x = c.args[k].number;
    if (it.text == "Y") p.y = c.args[k].number;
    if (it.text == "Z") p.z = c.args[k].number;
    if (it.text == "IJK") {
      const int j = c.args[k].next_sibling;
      ijk = {c.args[k].number, c.args[j].number, c.args[c.args[j].next_sibling].number};
    }
  }
}

}  // namespace

TEST(IppMoveRule, RebuildsEveryMoveOfPlanIppFromTheProgramAlone) {
  for (const char* normal : {"x+", "x-", "y-", "z+"}) {
    cmmcomp::measure::PlanOptions o;
    o.repeats = 1;
    const char axis = normal[0];
    const double sign = normal[1] == '+' ? 1.0 : -1.0;
    o.normal = {axis == 'x' ? sign : 0.0, axis == 'y' ? sign : 0.0, axis == 'z' ? sign : 0.0};
    o.nominal = {12.3456789, 400.0, -7.25};
    const std::vector<cmmcomp::measure::PlannedMove> plan = cmmcomp::measure::plan_experiment(o);
    const std::string program = cmmcomp::measure::format_ipp_program(plan, o);

    ipp::ProbingMoveTracker tracker;
    tracker.position_is({0, 0, 0});
    std::istringstream lines(program);
    std::string line;
    std::size_t next = 0;
    while (std::getline(lines, line)) {
      ipp::CommandLine c;
      ASSERT_EQ(ipp::parse_command(line, c), ipp::ParseStatus::kOk) << line;
      if (c.name == "SetProp") {
        for (int i = c.args.first(); i >= 0; i = c.args[i].next_sibling) {
          ipp::Property p{};
          ASSERT_TRUE(ipp::find_property(c.args[i].text.data(), c.args[i].text.size(), p));
          tracker.set_property(p, c.args[c.args[i].first_child].number);
        }
      } else if (c.name == "GoTo") {
        ipp::Point3 p, unused;
        point_of(c, p, unused);
        tracker.moved_to(p);
      } else if (c.name == "PtMeas") {
        ipp::Point3 nominal, ijk;
        point_of(c, nominal, ijk);
        const ipp::ReconstructedMove m = tracker.probing_move(nominal, ijk);
        ASSERT_TRUE(m.ok) << m.problem;
        ASSERT_LT(next, plan.size());
        const cmmcomp::measure::PlannedMove& want = plan[next++];
        const double tol = 2e-6;  // the program's numbers are at 1e-6
        EXPECT_NEAR(m.pv_mm_s, want.settings.pv_mm_s, tol);
        EXPECT_NEAR(m.pa_mm_s2, want.settings.pa_mm_s2, tol);
        EXPECT_NEAR(m.pd_mm, want.settings.pd_mm, tol);
        EXPECT_NEAR(m.av_mm_s, want.settings.av_mm_s, tol);
        EXPECT_NEAR(m.aa_mm_s2, want.settings.aa_mm_s2, tol);
        EXPECT_NEAR(m.ad_mm, want.settings.ad_mm, tol);
        // Y is the nominal point's (for x and z moves the plan puts it at the move's Y level).
        EXPECT_NEAR(m.y_mm, want.touch.y, tol);
        if (axis != 'y') {
          EXPECT_NEAR(m.y_mm, want.settings.y_mm, tol);
        }
        EXPECT_FALSE(m.own_positioning);
        EXPECT_NEAR(m.direction.x, -want.normal.x, 1e-12);
        EXPECT_NEAR(m.direction.y, -want.normal.y, 1e-12);
        EXPECT_NEAR(m.direction.z, -want.normal.z, 1e-12);
        tracker.probed(m);
      }
    }
    EXPECT_EQ(next, plan.size()) << normal;
  }
}

TEST(IppMoveRule, APtMeasThatPositionsItselfRunsFromWhereTheProbeStands) {
  ipp::ProbingMoveTracker t;
  for (const ipp::PropertyInfo& info : ipp::kProperties) t.set_property(info.property, 5.0);
  t.set_property(ipp::Property::kPtMeasApproach, 2.0);
  t.set_property(ipp::Property::kPtMeasRetract, 1.0);
  t.moved_to({0, 0, 0});
  t.moved_to({30, 100, 0});  // a GoTo that does not end at the pre-hit point
  // nominal (10, 100, 0), IJK (1, 0, 0): pre-hit (12, 100, 0), 18 mm from (30, 100, 0).
  ipp::ReconstructedMove m = t.probing_move({10, 100, 0}, {2, 0, 0});
  ASSERT_TRUE(m.ok);
  EXPECT_TRUE(m.own_positioning);
  EXPECT_DOUBLE_EQ(m.pd_mm, 18.0);
  EXPECT_DOUBLE_EQ(m.prehit.x, 12.0);
  EXPECT_DOUBLE_EQ(m.direction.x, -1.0);
  EXPECT_DOUBLE_EQ(m.y_mm, 100.0);
  t.probed(m);
  ipp::Point3 p;
  ASSERT_TRUE(t.position(p));
  EXPECT_DOUBLE_EQ(p.x, 11.0);  // retracted 1 mm along the normal
  // The next PtMeas on the same point: from the retract point, 1 mm to the pre-hit.
  m = t.probing_move({10, 100, 0}, {1, 0, 0});
  ASSERT_TRUE(m.ok);
  EXPECT_DOUBLE_EQ(m.pd_mm, 1.0);
  // With Retract = Approach the positioning has no length: the 1 µm floor.
  t.set_property(ipp::Property::kPtMeasRetract, 2.0);
  t.probed(m);
  m = t.probing_move({10, 100, 0}, {1, 0, 0});
  ASSERT_TRUE(m.ok);
  EXPECT_DOUBLE_EQ(m.pd_mm, 1e-3);
}

TEST(IppMoveRule, SaysWhatItCannotKnow) {
  ipp::ProbingMoveTracker t;
  EXPECT_FALSE(t.probing_move({0, 0, 0}, {1, 0, 0}).ok);  // no property known
  for (const ipp::PropertyInfo& info : ipp::kProperties) t.set_property(info.property, 5.0);
  ipp::ReconstructedMove m = t.probing_move({0, 0, 0}, {1, 0, 0});
  EXPECT_FALSE(m.ok);  // no position known (a proxy before the first GoTo)
  EXPECT_NE(std::string(m.problem).find("position"), std::string::npos);
  t.moved_to({5, 0, 0});  // the first GoTo: ends at the pre-hit point, start unknown
  m = t.probing_move({0, 0, 0}, {1, 0, 0});
  EXPECT_FALSE(m.ok);
  t.moved_to({9, 0, 0});
  t.moved_to({5, 0, 0});
  m = t.probing_move({0, 0, 0}, {1, 0, 0});
  ASSERT_TRUE(m.ok);
  EXPECT_DOUBLE_EQ(m.pd_mm, 4.0);
  EXPECT_FALSE(t.probing_move({0, 0, 0}, {0, 0, 0}).ok);  // IJK of no length
  t.position_unknown();  // a Home on a server the proxy does not see into
  EXPECT_FALSE(t.probing_move({0, 0, 0}, {1, 0, 0}).ok);
  t.moved_to({9, 0, 0});  // a GoTo from an unknown position: its length is unknown too
  t.moved_to({5, 0, 0});
  ASSERT_TRUE(t.probing_move({0, 0, 0}, {1, 0, 0}).ok);
  // An oblique normal: the pre-hit point lies along it.
  t.position_is({0, 0, 0});
  m = t.probing_move({0, 0, 0}, {3, 0, 4});
  ASSERT_TRUE(m.ok);
  EXPECT_NEAR(m.prehit.x, 3.0, 1e-12);
  EXPECT_NEAR(m.prehit.z, 4.0, 1e-12);
  EXPECT_NEAR(m.direction.z, -0.8, 1e-12);
}
