// SPDX-License-Identifier: MIT
/// @file The feed planner against an exhaustive grid search, its constraints, and its errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/planning/feed_planner.hpp>
#include <cmmcomp/planning/plan_report.hpp>
#include <string>
#include <vector>

namespace {

using cmmcomp::io::CompensationModelFile;
using cmmcomp::planning::FeedPlanner;
using cmmcomp::planning::FeedSetting;
using cmmcomp::planning::Mode;
using cmmcomp::planning::ModelAtY;
using cmmcomp::planning::PlanProblem;

CompensationModelFile shipped_model() {
  return CompensationModelFile(cmmcomp::io::default_model_file());
}

CompensationModelFile shipped_y_model() {
  return cmmcomp::io::load_compensation_model(std::string(CMMCOMP_SOURCE_DIR) +
                                              "/data/models/default-y.json");
}

/// A small domain inside the model's ranges, as the brute force's reference can cover finely.
PlanProblem small_domain(double budget_um) {
  PlanProblem p;
  p.budget_um = budget_um;
  p.pv_mm_s = {40, 70};
  p.pd_mm = {40, 55};
  p.av_mm_s = {8, 12};
  p.ad_mm = {5, 9};
  p.dwell_s = 0.8;
  p.smoothing_s = 0.04;
  p.grid_points = 5;
  p.edge_margin = 0;  // the box as given
  return p;
}

std::string text(const FeedSetting& s) {
  return "PV " + std::to_string(s.pv_mm_s) + " PD " + std::to_string(s.pd_mm) + " AV " +
         std::to_string(s.av_mm_s) + " AD " + std::to_string(s.ad_mm);
}

/// Re-judges the planner's answer and compares it with a 21^4 exhaustive grid: the planner is
/// feasible and at least as fast (it searches between the grid's points too).
void expect_at_least_as_good_as_brute_force(const FeedPlanner& planner, Mode mode) {
  const auto planned = planner.plan(mode);
  const auto brute = planner.brute_force(mode, 21);
  ASSERT_TRUE(brute.found) << "the test's budget must leave feasible settings";
  ASSERT_TRUE(planned.found);
  const auto again = planner.check(planned.setting, mode);
  EXPECT_TRUE(again.feasible);
  EXPECT_LE(again.point_bound_um, planner.problem().budget_um);
  EXPECT_LE(again.mae_bound_um, planner.problem().mae_limit_um);
  EXPECT_DOUBLE_EQ(again.time_per_point_s, planned.check.time_per_point_s);
  EXPECT_LE(planned.check.time_per_point_s, brute.check.time_per_point_s + 1e-9)
      << "planned " << planned.check.time_per_point_s << " s at " << text(planned.setting)
      << ", brute force " << brute.check.time_per_point_s << " s at " << text(brute.setting);
  // And it is not far from the exhaustive optimum's neighbourhood: within one grid step's time.
  EXPECT_GT(planned.check.time_per_point_s, brute.check.time_per_point_s - 0.05);
}

const FeedSetting kFastestCorner{70, 200, 40, 12, 60, 5};
const FeedSetting kSlowestCorner{40, 200, 55, 8, 60, 9};

/// A budget halfway between the bounds of the box's fastest and slowest corners, so that the
/// constraint is active at the optimum (the fastest corner is cut off).
PlanProblem cutting_budget(const CompensationModelFile& model, PlanProblem p, Mode mode) {
  p.budget_um = 1e9;
  const FeedPlanner wide(model, p);
  const double fast = wide.check(kFastestCorner, mode).point_bound_um;
  const double slow = wide.check(kSlowestCorner, mode).point_bound_um;
  EXPECT_GT(fast, slow) << "the fast corner must have the larger bound for this test";
  p.budget_um = 0.5 * (fast + slow);
  return p;
}

TEST(FeedPlanner, UncompensatedMatchesBruteForceWhereTheBudgetCutsTheDomain) {
  // Uncompensated, the shipped model's |RAE| + U95 is about 4.9 µm at the slow corner of this
  // box and 5.3 µm at the fast one.
  const auto model = shipped_model();
  const FeedPlanner planner(model, cutting_budget(model, small_domain(1), Mode::kUncompensated));
  EXPECT_FALSE(planner.check(kFastestCorner, Mode::kUncompensated).feasible);
  expect_at_least_as_good_as_brute_force(planner, Mode::kUncompensated);
}

TEST(FeedPlanner, CompensatedMaeLimitMatchesBruteForce) {
  // Compensated with a generous point budget, the MAE bound is what cuts the domain: put its
  // limit inside its range here.
  PlanProblem p = small_domain(2.0);
  p.mae_limit_um = 1e9;
  const FeedPlanner wide(shipped_model(), p);
  const double fastest_mae = wide.check(kFastestCorner, Mode::kCompensated).mae_bound_um;
  const double slowest_mae = wide.check(kSlowestCorner, Mode::kCompensated).mae_bound_um;
  ASSERT_GT(fastest_mae, slowest_mae);
  p.mae_limit_um = 0.5 * (fastest_mae + slowest_mae);
  const FeedPlanner planner(shipped_model(), p);
  EXPECT_FALSE(planner.check(kFastestCorner, Mode::kCompensated).feasible);
  expect_at_least_as_good_as_brute_force(planner, Mode::kCompensated);
}

// The production case: compensated, with the budget on U95(RAE) active. The shipped 5-input
// model's corner gain makes U95 largest at the box's corner, which this box's fast corner is.
TEST(FeedPlanner, CompensatedU95BudgetMatchesBruteForce) {
  PlanProblem p;
  p.pv_mm_s = {70, 100};
  p.pd_mm = {40, 60};
  p.av_mm_s = {12, 16};
  p.ad_mm = {5, 10};
  p.y_mm = {0};
  p.dwell_s = 0.8;
  p.smoothing_s = 0.04;
  p.grid_points = 5;
  p.budget_um = 1e9;
  const auto model = shipped_y_model();
  const FeedPlanner wide(model, p);
  const FeedSetting fast{100, 200, 40, 16, 60, 5};  // every input at an end: κ = 1
  const FeedSetting slow{70, 200, 60, 12, 60, 10};  // PV/PD/AV/AD mid-range, Y 0: κ = 0.04
  const double u_fast = wide.check(fast, Mode::kCompensated).point_bound_um;
  const double u_slow = wide.check(slow, Mode::kCompensated).point_bound_um;
  ASSERT_GT(u_fast, 1.5 * u_slow) << "the shipped 5-input model's corner gain";
  p.budget_um = 0.5 * (u_fast + u_slow);
  const FeedPlanner planner(model, p);
  EXPECT_FALSE(planner.check(fast, Mode::kCompensated).feasible);
  expect_at_least_as_good_as_brute_force(planner, Mode::kCompensated);
  // The constraint is active at the optimum: its U95 is the budget, to the search's tolerance.
  const auto planned = planner.plan(Mode::kCompensated);
  EXPECT_NEAR(planned.check.point_bound_um, p.budget_um, 0.01 * p.budget_um);
}

TEST(FeedPlanner, FiveInputModelHoldsAtEveryY) {
  PlanProblem p = small_domain(1);
  p.y_mm = {0, 250, 500};
  const auto model = shipped_y_model();
  p = cutting_budget(model, p, Mode::kUncompensated);
  const FeedPlanner planner(model, p);
  const auto planned = planner.plan(Mode::kUncompensated);
  ASSERT_TRUE(planned.found);
  for (double y : p.y_mm) {
    PlanProblem one = p;
    one.y_mm = {y};
    const FeedPlanner at_y(model, one);
    EXPECT_TRUE(at_y.check(planned.setting, Mode::kUncompensated).feasible) << "Y " << y;
  }
  expect_at_least_as_good_as_brute_force(planner, Mode::kUncompensated);
}

TEST(FeedPlanner, WithoutAnyFeasibleSettingItSaysSoAndHowFarTheBudgetIs) {
  const FeedPlanner planner(shipped_model(), small_domain(0.5));
  const auto r = planner.plan(Mode::kUncompensated);
  EXPECT_FALSE(r.found);
  EXPECT_GT(r.best_point_bound_um, 0.5);
  EXPECT_TRUE(std::isfinite(r.best_point_bound_um));
  const auto again = planner.check(r.best_point_setting, Mode::kUncompensated);
  EXPECT_DOUBLE_EQ(again.point_bound_um, r.best_point_bound_um);
}

TEST(FeedPlanner, TimePerPointIsTheTrapezoidsWithoutDwellOrSmoothing) {
  PlanProblem p = small_domain(1.0);
  p.dwell_s = 0;
  p.smoothing_s = 0;
  const FeedPlanner planner(shipped_model(), p);
  // PV 40 over PD 50 at PA 200 cruises (50 > 40²/200 = 8); AV 10 over AD 6 at AA 60 too.
  const double t = planner.time_per_point_s(FeedSetting{40, 200, 50, 10, 60, 6});
  EXPECT_NEAR(t, 50.0 / 40 + 40.0 / 200 + 6.0 / 10 + 10.0 / (2 * 60), 1e-9);
  p.dwell_s = 0.8;
  const FeedPlanner dwelling(shipped_model(), p);
  EXPECT_NEAR(dwelling.time_per_point_s(FeedSetting{40, 200, 50, 10, 60, 6}), t + 0.8, 1e-9);
}

TEST(FeedPlanner, TheSearchBoxIsTheLimitsWithinTheModelsRanges) {
  PlanProblem p;
  p.budget_um = 1;
  p.edge_margin = 0;
  p.pv_mm_s = {0, 60};  // model: 40–100
  p.ad_mm = {7, 1000};  // model: 5–15
  const FeedPlanner planner(shipped_model(), p);
  EXPECT_EQ(planner.pv_mm_s().lo, 40);
  EXPECT_EQ(planner.pv_mm_s().hi, 60);
  EXPECT_EQ(planner.ad_mm().lo, 7);
  EXPECT_EQ(planner.ad_mm().hi, 15);
  EXPECT_EQ(planner.pd_mm().lo, 40);
  EXPECT_EQ(planner.av_mm_s().hi, 16);
}

TEST(FeedPlanner, TheEdgeMarginKeepsTheSearchAwayFromTheModelsEdges) {
  PlanProblem p;
  p.budget_um = 1;
  p.edge_margin = 0.2;  // 20 % of each range: PV 40–100 → 52–88, AD 5–15 → 7–13
  const FeedPlanner planner(shipped_model(), p);
  EXPECT_DOUBLE_EQ(planner.pv_mm_s().lo, 52);
  EXPECT_DOUBLE_EQ(planner.pv_mm_s().hi, 88);
  EXPECT_DOUBLE_EQ(planner.ad_mm().lo, 7);
  EXPECT_DOUBLE_EQ(planner.ad_mm().hi, 13);
  EXPECT_DOUBLE_EQ(planner.av_mm_s().hi, 14.4);
  EXPECT_DOUBLE_EQ(planner.pd_mm().lo, 48);
}

/// Constructing a planner from `models` (one model, or a model per Y) and `p` throws a
/// ConfigError whose message holds `words`.
template <typename Models>
void expect_planner_error(const Models& models, const PlanProblem& p, const std::string& words) {
  try {
    const FeedPlanner planner(models, p);
    ADD_FAILURE() << "no error; expected one with '" << words << "'";
  } catch (const cmmcomp::ConfigError& e) {
    EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
  }
}

void expect_config_error(const CompensationModelFile& model,
                         const PlanProblem& p,
                         const std::string& words) {
  expect_planner_error(model, p, words);
}

TEST(FeedPlanner, BadProblemsAreClearErrors) {
  PlanProblem p = small_domain(1.0);
  auto bad = p;
  bad.budget_um = 0;
  expect_config_error(shipped_model(), bad, "budget");
  bad = p;
  bad.budget_um = std::nan("");
  expect_config_error(shipped_model(), bad, "budget");
  bad = p;
  bad.pv_mm_s = {120, 200};
  expect_config_error(shipped_model(), bad, "PV limits");
  bad = p;
  bad.pa_mm_s2 = {300, 500};
  expect_config_error(shipped_model(), bad, "trained at");
  bad = p;
  bad.y_mm = {600};
  expect_config_error(shipped_y_model(), bad, "outside the model's training range");
  bad = p;
  bad.ad_mm = {9, 3};
  expect_config_error(shipped_model(), bad, "range of AD");
  bad = p;
  bad.edge_margin = 0.5;
  expect_config_error(shipped_model(), bad, "edge margin");
  bad = p;
  bad.edge_margin = 0.3;
  bad.ad_mm = {5, 7};  // the margin leaves AD 8–12
  expect_config_error(shipped_model(), bad, "less the edge margin");

  auto v1 = cmmcomp::io::default_model_file();
  v1.interval = {};
  expect_config_error(CompensationModelFile(v1), p, "no interval calibration");
}

// Models per Y: each Y of the program is judged by its own model.

/// The shipped model with every half-width of its interval multiplied by `factor`: a model
/// that is less sure, as one trained where the machine is less repeatable would be.
CompensationModelFile widened_model(double factor) {
  auto f = cmmcomp::io::default_model_file();
  for (double& h : f.interval.half_width) h *= factor;
  return CompensationModelFile(f);
}

TEST(FeedPlannerModelsPerY, TheSameModelAtEveryYPlansAsOneModel) {
  PlanProblem p = cutting_budget(shipped_model(), small_domain(1), Mode::kUncompensated);
  p.y_mm = {0, 250, 500};
  const FeedPlanner one(shipped_model(), p);
  const FeedPlanner per_y(
      std::vector<ModelAtY>{{0, shipped_model()}, {250, shipped_model()}, {500, shipped_model()}},
      p);
  EXPECT_FALSE(one.models_per_y());
  EXPECT_TRUE(per_y.models_per_y());
  ASSERT_EQ(per_y.model_ids().size(), 3u);
  EXPECT_EQ(per_y.model_ids()[2], one.model_ids()[2]);
  for (const Mode mode : {Mode::kCompensated, Mode::kUncompensated}) {
    const auto a = one.plan(mode);
    const auto b = per_y.plan(mode);
    ASSERT_EQ(a.found, b.found);
    EXPECT_EQ(text(a.setting), text(b.setting));
    EXPECT_DOUBLE_EQ(a.check.time_per_point_s, b.check.time_per_point_s);
    EXPECT_DOUBLE_EQ(a.check.point_bound_um, b.check.point_bound_um);
  }
}

TEST(FeedPlannerModelsPerY, EachYIsJudgedByItsOwnModel) {
  // Y 0 and 250 by the shipped model, Y 500 by one whose U95 is 1.5 times as wide. A 4-input
  // model's prediction does not depend on Y, so uncompensated (|RAE| + U95) the wide model
  // binds at every setting: the per-Y plan is the wide model's plan, and its worst Y is 500.
  const auto wide = widened_model(1.5);
  PlanProblem p = small_domain(1);
  p.y_mm = {0, 250, 500};
  p = cutting_budget(wide, p, Mode::kUncompensated);
  const FeedPlanner per_y(
      std::vector<ModelAtY>{{500, wide}, {0, shipped_model()}, {250, shipped_model()}}, p);
  const FeedPlanner wide_everywhere(wide, p);
  const FeedPlanner shipped_everywhere(shipped_model(), p);
  const auto planned = per_y.plan(Mode::kUncompensated);
  const auto reference = wide_everywhere.plan(Mode::kUncompensated);
  ASSERT_TRUE(planned.found);
  ASSERT_TRUE(reference.found);
  EXPECT_EQ(text(planned.setting), text(reference.setting));
  EXPECT_DOUBLE_EQ(planned.check.point_bound_um, reference.check.point_bound_um);
  EXPECT_EQ(planned.check.worst_y_mm, 500);
  // The shipped model alone allows a faster setting: the wide model at Y 500 held the plan back.
  EXPECT_LT(shipped_everywhere.plan(Mode::kUncompensated).check.time_per_point_s,
            planned.check.time_per_point_s);
  expect_at_least_as_good_as_brute_force(per_y, Mode::kUncompensated);
}

TEST(FeedPlannerModelsPerY, TheSearchBoxLiesInsideEveryModelsRanges) {
  auto narrow = cmmcomp::io::default_model_file();
  narrow.model.ranges[0].hi = 80;  // PV 40–80 instead of 40–100
  PlanProblem p;
  p.budget_um = 1;
  p.y_mm = {0, 500};
  const FeedPlanner planner(
      std::vector<ModelAtY>{{0, shipped_model()}, {500, CompensationModelFile(narrow)}}, p);
  EXPECT_EQ(planner.pv_mm_s().lo, 40);
  EXPECT_EQ(planner.pv_mm_s().hi, 80);
  EXPECT_EQ(planner.ad_mm().hi, 15);
  // The order of the models does not matter: the narrow one first gives the same box.
  const FeedPlanner reversed(
      std::vector<ModelAtY>{{0, CompensationModelFile(narrow)}, {500, shipped_model()}}, p);
  EXPECT_EQ(reversed.pv_mm_s().lo, 40);
  EXPECT_EQ(reversed.pv_mm_s().hi, 80);
  EXPECT_EQ(reversed.ad_mm().hi, 15);
}

TEST(FeedPlannerModelsPerY, DisjointModelRangesNameTheOtherModels) {
  // Two models whose PV ranges do not overlap: the second model's error says that the limit it
  // missed was already narrowed by the first model, not the problem's own limit.
  auto low = cmmcomp::io::default_model_file();
  low.model.ranges[0].hi = 50;  // PV 40–50
  auto high = cmmcomp::io::default_model_file();
  high.model.ranges[0].lo = 60;  // PV 60–100
  PlanProblem p;
  p.budget_um = 1;
  p.y_mm = {0, 500};
  expect_planner_error(
      std::vector<ModelAtY>{{0, CompensationModelFile(low)}, {500, CompensationModelFile(high)}},
      p,
      "PV (the model for Y 500 mm) limits within the other models' ranges [40.000000, 50.000000] "
      "miss the model's training range [60.000000, 100.000000]");
}

void expect_per_y_error(const std::vector<ModelAtY>& models,
                        const PlanProblem& p,
                        const std::string& words) {
  expect_planner_error(models, p, words);
}

TEST(FeedPlannerModelsPerY, BadModelSetsAreClearErrors) {
  PlanProblem p = small_domain(1.0);
  p.y_mm = {0, 250};
  expect_per_y_error({}, p, "no model");
  expect_per_y_error({{0, shipped_model()}}, p, "no model for Y 250 mm (models for Y 0 mm)");
  expect_per_y_error(
      {{0, shipped_model()}, {250, shipped_model()}, {250, shipped_model()}}, p, "two models");
  expect_per_y_error({{0, shipped_model()}, {std::nan(""), shipped_model()}}, p, "Y is not finite");
  auto v1 = cmmcomp::io::default_model_file();
  v1.interval = {};
  expect_per_y_error({{0, shipped_model()}, {250, CompensationModelFile(v1)}},
                     p,
                     "the model for Y 250 mm has no interval calibration");
  // A 5-input model serves only Y inside its own training range.
  p.y_mm = {0, 600};
  expect_per_y_error({{0, shipped_model()}, {600, shipped_y_model()}},
                     p,
                     "Y 600 mm is outside the model's training range [0, 500] (the model for "
                     "Y 600 mm)");
}

using cmmcomp::planning::QualifiedReference;

QualifiedReference paper_like_map() {
  QualifiedReference q;
  q.sphere_y_mm = 250;
  q.map_y_mm = {0, 250, 500};
  q.map_um = {-3.7, -3.9, -6.8};
  return q;
}

/// The raw RAE and U95 the planner sees for `s` at one Y (an unqualified planner at that Y).
cmmcomp::planning::SettingCheck raw_at(const CompensationModelFile& model,
                                       PlanProblem p,
                                       const FeedSetting& s,
                                       double y) {
  p.y_mm = {y};
  p.qualified.reset();
  return FeedPlanner(model, p).check(s, Mode::kUncompensated);
}

TEST(FeedPlannerQualified, JudgesWhatTheMapAndTheQualificationLeave) {
  const CompensationModelFile model = shipped_y_model();
  PlanProblem p = small_domain(1e9);
  p.y_mm = {0, 250, 500};
  p.qualified = paper_like_map();
  const FeedPlanner planner(model, p);
  for (const FeedSetting& s : {kFastestCorner, kSlowestCorner}) {
    const auto sphere = raw_at(model, p, s, 250);
    double worst = -1, worst_residual = 0, worst_u = 0, worst_y = 0;
    for (double y : p.y_mm) {
      const auto raw = raw_at(model, p, s, y);
      const double residual =
          (raw.rae_um - sphere.rae_um) - (p.qualified->map_at_um(y) - p.qualified->map_at_um(250));
      const double u = std::hypot(raw.u95_rae_um, sphere.u95_rae_um);
      if (std::fabs(residual) + u > worst) {
        worst = std::fabs(residual) + u;
        worst_residual = residual;
        worst_u = u;
        worst_y = y;
      }
    }
    const auto c = planner.check(s, Mode::kUncompensated);
    EXPECT_NEAR(c.point_bound_um, worst, 1e-12) << text(s);
    EXPECT_NEAR(c.rae_um, worst_residual, 1e-12);
    EXPECT_NEAR(c.u95_rae_um, worst_u, 1e-12);
    EXPECT_DOUBLE_EQ(c.worst_y_mm, worst_y);
    // The static lag is gone: the qualified bound is far below the raw one.
    PlanProblem raw_problem = p;
    raw_problem.qualified.reset();
    const FeedPlanner raw_planner(model, raw_problem);
    EXPECT_LT(c.point_bound_um, raw_planner.check(s, Mode::kUncompensated).point_bound_um - 2);
    // The compensated bound does not change.
    EXPECT_DOUBLE_EQ(planner.check(s, Mode::kCompensated).point_bound_um,
                     raw_planner.check(s, Mode::kCompensated).point_bound_um);
  }
}

TEST(FeedPlannerQualified, PlansNoSlowerThanTheBruteForce) {
  const CompensationModelFile model = shipped_y_model();
  PlanProblem p = small_domain(1e9);
  p.y_mm = {0, 250, 500};
  p.qualified = paper_like_map();
  // The qualified bound is not monotone in speed (here the slowest corner's exceeds the
  // fastest's), so the budget lies halfway between the smallest bound of a 5^4 grid and the
  // fastest corner's: it cuts the fastest corner off and leaves part of the box feasible.
  const FeedPlanner wide(model, p);
  const double fast = wide.check(kFastestCorner, Mode::kUncompensated).point_bound_um;
  double smallest = fast;
  for (int a = 0; a < 5; ++a) {
    for (int b = 0; b < 5; ++b) {
      for (int c = 0; c < 5; ++c) {
        for (int d = 0; d < 5; ++d) {
          const FeedSetting s{40 + 7.5 * a, 200, 40 + 3.75 * b, 8 + 1.0 * c, 60, 5 + 1.0 * d};
          smallest = std::min(smallest, wide.check(s, Mode::kUncompensated).point_bound_um);
        }
      }
    }
  }
  ASSERT_LT(smallest, fast - 0.05);
  p.budget_um = 0.5 * (smallest + fast);
  const FeedPlanner planner(model, p);
  expect_at_least_as_good_as_brute_force(planner, Mode::kUncompensated);
}

TEST(FeedPlannerQualified, AModelPerYJudgesTheSphereByItsModel) {
  // The same 4-input model at every Y predicts the same lag everywhere, so what remains is the
  // map's difference alone: at Y 500, −(−6.8 − −3.9) = +2.9 µm.
  PlanProblem p = small_domain(1e9);
  p.y_mm = {0, 250, 500};
  p.qualified = paper_like_map();
  const FeedPlanner same(
      std::vector<ModelAtY>{{0, shipped_model()}, {250, shipped_model()}, {500, shipped_model()}},
      p);
  const auto c = same.check(kFastestCorner, Mode::kUncompensated);
  EXPECT_DOUBLE_EQ(c.worst_y_mm, 500);
  EXPECT_NEAR(c.rae_um, 2.9, 1e-12);
  // With the 5-input model at the sphere's Y only, the sphere's lag is that model's: the
  // residual at Y 500 is the 4-input model's lag there less the 5-input model's at Y 250.
  const FeedPlanner mixed(
      std::vector<ModelAtY>{{0, shipped_model()}, {250, shipped_y_model()}, {500, shipped_model()}},
      p);
  PlanProblem at_500 = p;
  at_500.y_mm = {500};
  at_500.qualified.reset();
  const double rae_500 =
      FeedPlanner(shipped_model(), at_500).check(kFastestCorner, Mode::kUncompensated).rae_um;
  const double rae_sphere = raw_at(shipped_y_model(), p, kFastestCorner, 250).rae_um;
  const double expected = (rae_500 - rae_sphere) - (-6.8 - -3.9);
  ASSERT_GT(std::fabs(expected - 2.9), 0.05) << "the two models must differ at the sphere";
  PlanProblem only_500 = p;
  only_500.y_mm = {500};
  const FeedPlanner mixed_500(
      std::vector<ModelAtY>{{250, shipped_y_model()}, {500, shipped_model()}}, only_500);
  EXPECT_NEAR(mixed_500.check(kFastestCorner, Mode::kUncompensated).rae_um, expected, 1e-12);
  EXPECT_GE(mixed.check(kFastestCorner, Mode::kUncompensated).point_bound_um, std::fabs(expected));
}

TEST(FeedPlannerQualified, ItsErrorsAreClear) {
  PlanProblem p = small_domain(1.0);
  p.y_mm = {0, 250, 500};
  p.qualified = paper_like_map();
  expect_planner_error(shipped_model(), p, "needs a model that sees Y");
  expect_planner_error(
      std::vector<ModelAtY>{{0, shipped_model()}, {500, shipped_model()}},
      [&] {
        PlanProblem q = p;
        q.y_mm = {0, 500};
        return q;
      }(),
      "the reference sphere's Y 250 mm has no model (models for Y 0, 500 mm)");
  PlanProblem far = p;
  far.qualified->sphere_y_mm = 700;
  far.qualified->map_y_mm.push_back(700);
  far.qualified->map_um.push_back(-8.0);
  expect_planner_error(shipped_y_model(), far, "the reference sphere's Y 700 mm is outside");
  PlanProblem unsorted = p;
  unsorted.qualified->map_y_mm = {0, 500, 250};
  expect_planner_error(shipped_y_model(), unsorted, "ascend");
  // Beyond its nodes the map is only held flat: it must cover the program and the sphere.
  PlanProblem short_map = p;
  short_map.qualified->map_y_mm = {0, 250};
  short_map.qualified->map_um = {-3.7, -3.9};
  expect_planner_error(
      shipped_y_model(), short_map, "the reversal map covers Y 0 to 250 mm, not Y 500 mm");
  // A 5-input model at the sphere's Y must have been trained there.
  PlanProblem per_y = p;
  per_y.y_mm = {0};
  per_y.qualified->sphere_y_mm = 600;
  per_y.qualified->map_y_mm = {0, 600};
  per_y.qualified->map_um = {-3.7, -7.5};
  expect_planner_error(std::vector<ModelAtY>{{0, shipped_model()}, {600, shipped_y_model()}},
                       per_y,
                       "the reference sphere's Y 600 mm is outside the model's training range");
}

}  // namespace

namespace {

TEST(FeedPlanner, AModelCalibratedAtAnotherCoverageIsRefusedNamingBoth) {
  PlanProblem p = small_domain(5.0);
  // The shipped model's interval is at 95 %: a budget stated at 90 % cannot use it.
  p.coverage = 0.90;
  try {
    const FeedPlanner planner(shipped_model(), p);
    ADD_FAILURE() << "a budget at 90 % planned with a 95 % interval";
  } catch (const cmmcomp::ConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("calibrated at 95 % coverage, the budget is at 90 %"), std::string::npos)
        << what;
  }
  // A model whose interval was calibrated at 50 % is refused at the default 95 %.
  CompensationModelFile half = shipped_model();
  std::visit([](auto& f) { f.interval.coverage = 0.5; }, half);
  p.coverage = 0.95;
  EXPECT_THROW(FeedPlanner(half, p), cmmcomp::ConfigError);
  p.coverage = 0.5;
  EXPECT_NO_THROW(FeedPlanner(half, p));
}

// Training conditions (docs/planner.md): from the model, given within its range, or refused.
TEST(PlanConditions, FromTheModelGivenOrRefused) {
  using cmmcomp::io::ConditionRange;
  using cmmcomp::io::TrainingConditions;
  using cmmcomp::planning::GivenConditions;
  using cmmcomp::planning::resolve_conditions;
  TrainingConditions a;
  a.pa_mm_s2 = ConditionRange{100.0, 400.0};
  a.aa_mm_s2 = ConditionRange{60.0, 60.0};
  a.dwell_s = 0.5;
  a.smoothing_s = 0.05;
  const auto from_model = resolve_conditions({&a}, {"a"}, GivenConditions{});
  EXPECT_EQ(from_model.pa_mm_s2, 400.0);  // the highest trained at
  EXPECT_EQ(from_model.aa_mm_s2, 60.0);
  EXPECT_EQ(from_model.dwell_s, 0.5);
  EXPECT_EQ(from_model.smoothing_s, 0.05);
  EXPECT_EQ(from_model.timing_source, "the model's");
  // Two models: the highest PA both were trained at.
  TrainingConditions b = a;
  b.pa_mm_s2 = ConditionRange{200.0, 300.0};
  EXPECT_EQ(resolve_conditions({&a, &b}, {"a", "b"}, GivenConditions{}).pa_mm_s2, 300.0);
  GivenConditions given;
  given.pa_mm_s2 = 250.0;
  given.dwell_s = 0.505;
  given.smoothing_s = 0.05;
  given.machine_label = "the controller of m.toml";
  const auto with_given = resolve_conditions({&a}, {"a"}, given);
  EXPECT_EQ(with_given.pa_mm_s2, 250.0);
  EXPECT_EQ(with_given.dwell_s, 0.505);
  EXPECT_EQ(with_given.timing_source, "the controller of m.toml");
  const auto refused = [](const std::vector<const TrainingConditions*>& m,
                          const GivenConditions& g) -> std::string {
    std::vector<std::string> ids(m.size(), "m1");
    try {
      resolve_conditions(m, ids, g);
    } catch (const cmmcomp::ConfigError& e) {
      return e.what();
    }
    return "";
  };
  given.pa_mm_s2 = 1200.0;  // outside the model's PA
  EXPECT_NE(refused({&a}, given).find("--trained-pa 1200 mm/s², but model m1 was trained at PA"),
            std::string::npos);
  given.pa_mm_s2.reset();
  given.dwell_s = 1.128;  // another controller setting than the model's
  EXPECT_NE(refused({&a}, given).find("the controller of m.toml has a controller dwell of 1.128 s"),
            std::string::npos);
  const TrainingConditions none;  // a format-3 file
  EXPECT_NE(refused({&none}, GivenConditions{}).find("does not record the PA"), std::string::npos);
  GivenConditions accelerations;
  accelerations.pa_mm_s2 = 200.0;
  accelerations.aa_mm_s2 = 60.0;
  EXPECT_NE(refused({&none}, accelerations).find("does not record the controller dwell"),
            std::string::npos);
  accelerations.dwell_s = 1.128;
  accelerations.smoothing_s = 0.099;
  accelerations.machine_label = "the controller of m.toml";
  EXPECT_EQ(refused({&none}, accelerations), "");
  TrainingConditions c = a;
  c.pa_mm_s2 = ConditionRange{500.0, 600.0};  // does not overlap a's
  EXPECT_NE(refused({&a, &c}, GivenConditions{}).find("do not overlap"), std::string::npos);
}

}  // namespace

namespace cmmcomp::planning {
namespace {

TEST(PlanCapabilities, TheMachinesCapabilitiesNarrowTheLimitsAndAnEmptyOneIsAnError) {
  motion::ControllerCapabilities caps = motion::fixed_timing_capabilities(0.5, 0.05);
  caps[motion::Setting::kPositioningSpeed] = {0.001, 0.5};     // 1 .. 500 mm/s
  caps[motion::Setting::kPositioningAccel] = {0.010, 1.2};     // 10 .. 1200 mm/s²
  caps[motion::Setting::kApproachSpeed] = {0.0005, 0.020};     // 0.5 .. 20 mm/s
  caps[motion::Setting::kApproachDistance] = {0.0005, 0.015};  // 0.5 .. 15 mm
  PlanProblem p;
  p.pv_mm_s = {0.0, 1e9};
  p.av_mm_s = {10.0, 40.0};
  p.ad_mm = {2.0, 1e9};
  restrict_to_capabilities(p, caps, "m.toml");
  EXPECT_DOUBLE_EQ(p.pv_mm_s.lo, 1.0);
  EXPECT_DOUBLE_EQ(p.pv_mm_s.hi, 500.0);
  EXPECT_DOUBLE_EQ(p.pa_mm_s2.hi, 1200.0);
  EXPECT_DOUBLE_EQ(p.av_mm_s.lo, 10.0);  // the tighter of the two ends
  EXPECT_DOUBLE_EQ(p.av_mm_s.hi, 20.0);
  EXPECT_DOUBLE_EQ(p.ad_mm.lo, 2.0);
  EXPECT_DOUBLE_EQ(p.ad_mm.hi, 15.0);
  // AA's capability is MoveLimits' (fixed_timing_capabilities): the problem's 1e9 narrows to
  // its 1e6 mm/s², and a problem range inside it stays.
  EXPECT_DOUBLE_EQ(p.aa_mm_s2.hi, 1e6);
  PlanProblem inside;
  inside.aa_mm_s2 = {30.0, 90.0};
  restrict_to_capabilities(inside, caps, "m.toml");
  EXPECT_DOUBLE_EQ(inside.aa_mm_s2.lo, 30.0);
  EXPECT_DOUBLE_EQ(inside.aa_mm_s2.hi, 90.0);

  PlanProblem q;
  q.av_mm_s = {25.0, 40.0};
  try {
    restrict_to_capabilities(q, caps, "m.toml");
    FAIL() << "AV 25..40 against 0.5..20 was accepted";
  } catch (const ConfigError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("--av 25:40"), std::string::npos) << msg;
    EXPECT_NE(msg.find("m.toml (AV 0.5 .. 20)"), std::string::npos) << msg;
  }
}

}  // namespace
}  // namespace cmmcomp::planning
