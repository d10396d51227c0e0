// SPDX-License-Identifier: MIT
/// @file study::fastest_qualified_cycle and fastest_compensated_cycle against a brute force (each
/// cycle of a small grid judged alone), what their rules mean on the twin, and the document.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/study/cycle_speedup.hpp>
#include <cmmcomp/study/report.hpp>
#include <cmmcomp/vc/twin_source.hpp>
#include <string>
#include <vector>

namespace cmmcomp::study {
namespace {

constexpr double kPd = 40.0;

/// More than one chunk of the search (64 cycles), small enough to judge each alone.
CycleGrid small_grid(const dynamics::Machine& m) {
  CycleGrid g;
  g.pv_mm_s = {100, 200};
  g.pa_mm_s2 = {600, 1200};
  g.av_mm_s = {6, 10, 12};
  g.aa_mm_s2 = {300};
  g.ad_mm = {0.5, 3};
  g.dwell_s = {0, 0.1};
  g.smoothing_s = {0, 1.0 / m.parameters.mode_frequency_hz};
  return g;
}

CycleRules two_y() {
  CycleRules r;
  r.y_mm = {0.0, 500.0};
  return r;
}

/// The grid of the single cycle at index `i` of the combination order (PV outermost).
CycleGrid single(const CycleGrid& g, std::size_t i) {
  CycleGrid one;
  std::vector<double> CycleGrid::*members[] = {&CycleGrid::smoothing_s,
                                               &CycleGrid::dwell_s,
                                               &CycleGrid::ad_mm,
                                               &CycleGrid::aa_mm_s2,
                                               &CycleGrid::av_mm_s,
                                               &CycleGrid::pa_mm_s2,
                                               &CycleGrid::pv_mm_s};
  for (auto member : members) {
    const std::vector<double>& levels = g.*member;
    one.*member = {levels[i % levels.size()]};
    i /= levels.size();
  }
  return one;
}

std::size_t combinations(const CycleGrid& g) {
  return g.pv_mm_s.size() * g.pa_mm_s2.size() * g.av_mm_s.size() * g.aa_mm_s2.size() *
         g.ad_mm.size() * g.dwell_s.size() * g.smoothing_s.size();
}

/// The brute force: every cycle judged alone, the fastest that passes (the first in grid order
/// among equal times).
template <typename Search>
CycleChoice brute_force(const CycleGrid& g, const Search& search) {
  CycleChoice best;
  for (std::size_t i = 0; i < combinations(g); ++i) {
    const CycleChoice c = search(single(g, i));
    if (c.found && (!best.found || c.time_s < best.time_s)) best = c;
  }
  return best;
}

void expect_same_cycle(const CycleChoice& a, const CycleChoice& b) {
  ASSERT_EQ(a.found, b.found);
  if (!a.found) return;
  EXPECT_EQ(a.time_s, b.time_s);
  EXPECT_EQ(a.cycle.positioning_speed, b.cycle.positioning_speed);
  EXPECT_EQ(a.cycle.approach_speed, b.cycle.approach_speed);
  EXPECT_EQ(a.cycle.approach_distance, b.cycle.approach_distance);
  EXPECT_EQ(a.cycle.dwell, b.cycle.dwell);
  EXPECT_EQ(a.cycle.smoothing, b.cycle.smoothing);
}

TEST(CycleSpeedup, TheQualifiedSearchFindsTheBruteForcesFastestPassingCycle) {
  const dynamics::Machine m = dynamics::default_machine();
  const CycleGrid g = small_grid(m);
  ASSERT_GT(combinations(g), 64u);
  // Two variants keep the brute force short; the search's robustness is the same code.
  const std::vector<dynamics::Machine> variants{robustness_variants(m)[4],
                                                robustness_variants(m)[7]};
  auto search = [&](const CycleGrid& grid) {
    return fastest_qualified_cycle(m, variants, kPd, grid, two_y());
  };
  const CycleChoice fast = search(g);
  const CycleChoice slow = brute_force(g, search);
  expect_same_cycle(fast, slow);
  ASSERT_TRUE(fast.found);
  EXPECT_LE(fast.check.residual_um, two_y().resolved().allowance_um());
  EXPECT_LE(fast.check.mae_um, two_y().mae_limit_um);
}

TEST(CycleSpeedup, TheCompensatedSearchFindsTheBruteForcesFastestPassingCycle) {
  const dynamics::Machine truth = dynamics::default_machine();
  dynamics::Machine model = truth;  // a model 3 % off in the hose's delayed term
  model.parameters.hose_accel_lag_s2 *= 1.03;
  const CycleGrid g = small_grid(truth);
  auto search = [&](const CycleGrid& grid) {
    return fastest_compensated_cycle(truth, model, kPd, grid, two_y());
  };
  expect_same_cycle(search(g), brute_force(g, search));
}

TEST(CycleSpeedup, APerfectModelLeavesNothingAndTheMaeLimitBinds) {
  const dynamics::Machine m = dynamics::default_machine();
  const CycleChoice c = fastest_compensated_cycle(m, m, kPd, default_cycle_grid(m), two_y());
  ASSERT_TRUE(c.found);
  EXPECT_EQ(c.check.residual_um, 0.0);
  EXPECT_EQ(c.check.binding, "MAE");
  // The oracle is never slower than the qualified machine with the same freedom.
  const CycleChoice q =
      fastest_qualified_cycle(m, robustness_variants(m), kPd, default_cycle_grid(m), two_y());
  ASSERT_TRUE(q.found);
  EXPECT_LE(c.time_s, q.time_s);
}

TEST(CycleSpeedup, EveryChosenCycleIsOneTheControllerAcceptsAndTouchesAtConstantSpeed) {
  const dynamics::Machine m = dynamics::default_machine();
  const CycleChoice c = fastest_compensated_cycle(m, m, kPd, default_cycle_grid(m), two_y());
  ASSERT_TRUE(c.found);
  EXPECT_TRUE(dynamics::capability_problem(m, c.cycle).empty());
  motion::MoveProfile profile;
  ASSERT_TRUE(ok(motion::MoveProfile::plan(c.cycle, profile)));
  EXPECT_LT(profile.instants().approach_accel_end, profile.instants().touch);
  EXPECT_DOUBLE_EQ(profile.instants().touch, c.time_s);
}

TEST(CycleSpeedup, BadRulesAndGridsAreConfigErrors) {
  const dynamics::Machine m = dynamics::default_machine();
  CycleRules tight;
  tight.budget_um = 0.1;  // below the repeatability's own 95 %
  EXPECT_THROW(tight.resolved(), ConfigError);
  CycleRules no_y;
  no_y.y_mm.clear();
  EXPECT_THROW(no_y.resolved(), ConfigError);
  CycleGrid empty = small_grid(m);
  empty.dwell_s.clear();
  EXPECT_THROW(fastest_compensated_cycle(m, m, kPd, empty, two_y()), ConfigError);
}

TEST(CycleSpeedup, TheDocumentRendersEveryRowAndTheTargets) {
  const dynamics::Machine m = dynamics::default_machine();
  CycleSubject s;
  s.truth = m;
  s.has_model = true;
  s.model = m;
  const CycleSpeedupResult r = cycle_speedup({s}, {kPd}, two_y());
  ASSERT_EQ(r.rows.size(), 1u);
  // The two speed-ups and the two length tests.
  ASSERT_EQ(r.targets.size(), 4u);
  EXPECT_EQ(r.rows[0].length_test_seeds, 5);
  const std::string text = render_markdown(cycle_speedup_document(r));
  EXPECT_NE(text.find("| paper-default | 40 |"), std::string::npos) << text;
  EXPECT_NE(text.find("oracle"), std::string::npos);
  EXPECT_NE(text.find(" of 5 |"), std::string::npos) << text;
}

TEST(CycleSpeedup, ACampaignIdentifiesTheMachineDownToTheNoise) {
  // A small campaign from the shipped start file: the fit reaches the truth's own cost (the
  // noise's) within a few percent, and the hose's delayed term and time constant come back
  // within 3 of their reported sigma.
  CampaignIdentification c;
  c.moves = 40;
  c.seed = 3;
  c.start = dynamics::load_machine(CMMCOMP_SOURCE_DIR "/data/machines/default-start.toml");
  c.frequency_starts = {0.8, 1.0};
  const dynamics::Machine truth = dynamics::default_machine();
  const IdentifiedModel m = identify_from_campaign(truth, c);
  EXPECT_EQ(m.residuals, 4 * c.moves);
  EXPECT_LT(m.final_cost, 1.1 * m.truth_cost);
  for (std::size_t i = 0; i < m.parameters.size(); ++i) {
    if (m.parameters[i] != "hose.accel_lag_s2" && m.parameters[i] != "hose.time_constant_s") {
      continue;
    }
    const double off = std::abs(m.fitted_values[i] / m.truth_values[i] - 1.0);
    EXPECT_LE(off, 3.0 * m.relative_sigma[i]) << m.parameters[i];
  }
  EXPECT_EQ(m.machine.parameters.controller_dwell_s, truth.parameters.controller_dwell_s);
  EXPECT_THROW(identify_from_campaign(truth, CampaignIdentification{5, 1, c.start}), ConfigError);
}

TEST(TwinSource, AnswersItsMachinesTouchErrorAlongTheApproach) {
  const dynamics::Machine m = dynamics::default_machine();
  vc::TwinSource source("twin", m);
  compensation::MoveRequest request;
  request.direction = {-1.0, 0.0, 0.0};
  request.pv_mm_s = 100;
  request.pa_mm_s2 = 600;
  request.pd_mm = 40;
  request.av_mm_s = 8;
  request.aa_mm_s2 = 300;
  request.ad_mm = 3;
  request.y_mm = 400;
  const vc::Answer a = source.ask(request);
  ASSERT_TRUE(a.usable) << a.note;
  const double rae = dynamics::BridgeSimulator(m)
                         .simulate(motion::probing_move_mm(100, 600, 40, 8, 300, 3), 0.4)
                         .errors_um.rae;
  EXPECT_EQ(a.rae_um, rae);
  EXPECT_EQ(a.correction_um[0], -rae);
  EXPECT_EQ(a.correction_um[1], 0.0);
  // A move the controller refuses is an unusable answer with its reason, not an exception.
  request.pa_mm_s2 = 5000;
  const vc::Answer refused = source.ask(request);
  EXPECT_FALSE(refused.usable);
  EXPECT_FALSE(refused.note.empty());
}

}  // namespace
}  // namespace cmmcomp::study
