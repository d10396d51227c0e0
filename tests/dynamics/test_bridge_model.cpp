// SPDX-License-Identifier: MIT
/// @file The digital twin on the default machine: properties of a simulated move, never values.
///
/// The model and the default machine are being recalibrated, so nothing here hard-codes a
/// simulated error: the tests check what must hold for any calibration (orderings, consistency
/// of the trace with the result, determinism, convergence, error reporting).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::dynamics {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kBaselineY = 0.250;  // [m]

bool contains(const std::string& s, const std::string& part) {
  return s.find(part) != std::string::npos;
}

SimulationOptions traced() {
  SimulationOptions o;
  o.record_trace = true;
  return o;
}

/// The traced baseline move at Y = 250 mm, simulated once for the tests that only read it.
const SimulationResult& baseline_traced() {
  static const SimulationResult result = [] {
    BridgeSimulator sim(default_machine(), traced());
    return sim.simulate(motion::baseline_move(), kBaselineY);
  }();
  return result;
}

/// Traced and untraced runs stop the integrator at different output times, so they agree to the
/// integration tolerance (1e-11 m = 1e-5 µm on the tip error), not to the bit.
void expect_close_errors(const errors::DynamicErrors& a, const errors::DynamicErrors& b) {
  constexpr double kTolUm = 1e-4;
  EXPECT_NEAR(a.mpe, b.mpe, kTolUm);
  EXPECT_NEAR(a.rpe, b.rpe, kTolUm);
  EXPECT_NEAR(a.mae, b.mae, kTolUm);
  EXPECT_NEAR(a.rae, b.rae, kTolUm);
}

void expect_same_errors(const errors::DynamicErrors& a, const errors::DynamicErrors& b) {
  EXPECT_EQ(a.mpe, b.mpe);
  EXPECT_EQ(a.rpe, b.rpe);
  EXPECT_EQ(a.mae, b.mae);
  EXPECT_EQ(a.rae, b.rae);
}

/// The message of the cmmcomp::Error `f` throws ("no error" if none).
template <typename F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(BridgeSimulator, BaselineErrorsAreFiniteAndOrdered) {
  const errors::DynamicErrors& e = baseline_traced().errors_um;
  ASSERT_TRUE(std::isfinite(e.mpe) && std::isfinite(e.rpe) && std::isfinite(e.mae) &&
              std::isfinite(e.rae));
  EXPECT_GT(e.mpe, 0.0);
  EXPECT_GE(e.mpe, std::fabs(e.rpe));  // RPE is one sample of the positioning phase
  EXPECT_GE(e.mae, std::fabs(e.rae));  // RAE is the last sample of the approach
  EXPECT_GE(e.mae, 0.0);
}

TEST(BridgeSimulator, ResultCarriesTheInstantsOfTheControlledProfile) {
  // The machine's controller runs the move: its dwell and smoothing shape the profile.
  const MachineParameters& p = default_machine().parameters;
  ASSERT_GT(p.controller_dwell_s, 0.0);
  ASSERT_GT(p.controller_smoothing_s, 0.0);
  motion::MoveProfile profile;
  ASSERT_EQ(motion::MoveProfile::plan(controlled_move(p, motion::baseline_move()), profile),
            Status::kOk);
  const motion::PhaseInstants& a = baseline_traced().instants;
  const motion::PhaseInstants& b = profile.instants();
  EXPECT_EQ(a.positioning_accel_end, b.positioning_accel_end);
  EXPECT_EQ(a.positioning_decel_start, b.positioning_decel_start);
  EXPECT_EQ(a.positioning_end, b.positioning_end);
  EXPECT_EQ(a.approach_start, b.approach_start);
  EXPECT_EQ(a.approach_accel_end, b.approach_accel_end);
  EXPECT_EQ(a.touch, b.touch);
  EXPECT_NEAR(a.approach_start - a.positioning_end, p.controller_dwell_s, 1e-12);
  // Smoothing lengthens the 0.2 s ramp by the smoothing time.
  EXPECT_NEAR(a.positioning_accel_end, 0.2 + p.controller_smoothing_s, 1e-12);
}

TEST(BridgeSimulator, TipLagFollowsTheModeShapeAlongTheBeam) {
  // Errors grow monotonically from the drive side to the far end (Table 2's trend).
  BridgeSimulator sim(default_machine());
  double last = 0.0;
  for (const double y : {0.0, 0.125, 0.25, 0.375, 0.5}) {
    const double mpe = sim.simulate(motion::baseline_move(), y).errors_um.mpe;
    EXPECT_GT(mpe, last) << "Y " << y;
    last = mpe;
  }
}

TEST(BridgeSimulator, WithoutTheModeExcitationOrTheHoseThereIsNoError) {
  // An ideal machine (no participation, no hose drag) has no dynamic error at all: the servo's
  // error moves scale and tip together.
  Machine m = default_machine();
  m.parameters.mode_participation = 1e-3;  // the smallest accepted value
  m.parameters.hose_viscous_drag_Ns_per_m = 0.0;
  m.parameters.hose_coulomb_drag_N = 0.0;
  m.parameters.hose_accel_lag_s2 = 0.0;
  const SimulationResult r = BridgeSimulator(m).simulate(motion::baseline_move(), 0.25);
  const SimulationResult full =
      BridgeSimulator(default_machine()).simulate(motion::baseline_move(), 0.25);
  EXPECT_LT(r.errors_um.mpe, 0.02 * full.errors_um.mpe);
  EXPECT_LT(std::fabs(r.errors_um.rae), 1e-3);
}

TEST(BridgeSimulator, DwellErasesThePositioningHistoryFromTheApproach) {
  // MAE and RAE do not depend on PV or PD once the dwell has let the hose link settle.
  BridgeSimulator sim(default_machine());
  const SimulationResult slow =
      sim.simulate(motion::probing_move_mm(40, 200, 40, 12, 60, 10), 0.25);
  const SimulationResult fast =
      sim.simulate(motion::probing_move_mm(100, 200, 80, 12, 60, 10), 0.25);
  EXPECT_NEAR(slow.errors_um.rae, fast.errors_um.rae, 1e-3);
  EXPECT_NEAR(slow.errors_um.mae, fast.errors_um.mae, 1e-3);
  EXPECT_GT(fast.errors_um.mpe, slow.errors_um.mpe);
}

TEST(BridgeSimulator, TraceRunsFromZeroToTheTouchThroughEveryInstant) {
  const SimulationResult& r = baseline_traced();
  const auto& trace = r.trace;
  ASSERT_GE(trace.size(), 10u);
  EXPECT_EQ(trace.front().t_s, 0.0);
  EXPECT_EQ(trace.back().t_s, r.instants.touch);
  for (std::size_t i = 1; i < trace.size(); ++i) {
    ASSERT_GT(trace[i].t_s, trace[i - 1].t_s) << "sample " << i;
  }
  // The trace rate is 1 kHz by default: no gap much longer than a millisecond.
  for (std::size_t i = 1; i < trace.size(); ++i) {
    ASSERT_LE(trace[i].t_s - trace[i - 1].t_s, 1e-3 * (1 + 1e-6)) << "sample " << i;
  }
  auto has_sample_at = [&trace](double t) {
    return std::any_of(
        trace.begin(), trace.end(), [t](const TraceSample& s) { return s.t_s == t; });
  };
  EXPECT_TRUE(has_sample_at(r.instants.positioning_accel_end));
  EXPECT_TRUE(has_sample_at(r.instants.positioning_end));
  EXPECT_TRUE(has_sample_at(r.instants.approach_accel_end));
  EXPECT_TRUE(has_sample_at(r.instants.touch));
}

TEST(BridgeSimulator, TraceColumnsAreFiniteAndConsistent) {
  const SimulationResult& r = baseline_traced();
  const motion::ProbingMove m = motion::baseline_move();
  for (std::size_t i = 0; i < r.trace.size(); ++i) {
    const TraceSample& s = r.trace[i];
    SCOPED_TRACE("sample " + std::to_string(i) + " t=" + std::to_string(s.t_s));
    ASSERT_TRUE(std::isfinite(s.commanded_mm) && std::isfinite(s.scale_mm) &&
                std::isfinite(s.tip_mm) && std::isfinite(s.error_um) &&
                std::isfinite(s.velocity_mm_s) && std::isfinite(s.acceleration_mm_s2));
    // The scale follows the command through the servo error: small next to the move.
    ASSERT_LT(std::fabs(s.scale_mm - s.commanded_mm), 1.0);
    // e = tip − scale (d = +1), µm vs mm.
    ASSERT_NEAR(s.tip_mm - s.scale_mm, s.error_um / 1000.0, 1e-9);
  }
  // The command ends at the touch point PD + AD and starts at rest at 0.
  const double travel_mm = (m.positioning_distance + m.approach_distance) * 1e3;
  EXPECT_EQ(r.trace.front().commanded_mm, 0.0);
  EXPECT_NEAR(r.trace.back().commanded_mm, travel_mm, 1e-9);
}

TEST(BridgeSimulator, ReExtractingFromTheTraceGivesTheResult) {
  const SimulationResult& r = baseline_traced();
  std::vector<double> t;
  std::vector<double> e;
  for (const TraceSample& s : r.trace) {
    t.push_back(s.t_s);
    e.push_back(s.error_um);
  }
  errors::DynamicErrors again;
  ASSERT_EQ(errors::extract_dynamic_errors(
                errors::TraceView{t.data(), e.data(), t.size()}, r.instants, +1, again),
            Status::kOk);
  EXPECT_NEAR(again.mpe, r.errors_um.mpe, 1e-9);
  EXPECT_NEAR(again.rpe, r.errors_um.rpe, 1e-9);
  EXPECT_NEAR(again.mae, r.errors_um.mae, 1e-9);
  EXPECT_NEAR(again.rae, r.errors_um.rae, 1e-9);
}

TEST(BridgeSimulator, RecordingTheTraceDoesNotChangeTheResult) {
  BridgeSimulator sim(default_machine());
  const SimulationResult r = sim.simulate(motion::baseline_move(), kBaselineY);
  EXPECT_TRUE(r.trace.empty());
  expect_close_errors(r.errors_um, baseline_traced().errors_um);
}

TEST(BridgeSimulator, RepeatedAndInterleavedMovesGiveIdenticalResults) {
  BridgeSimulator sim(default_machine());
  const SimulationResult first = sim.simulate(motion::baseline_move(), kBaselineY);
  motion::ProbingMove other = motion::baseline_move();
  other.positioning_speed = 0.100;
  other.approach_speed = 0.016;
  other.positioning_distance = 0.080;
  const SimulationResult between = sim.simulate(other, 1.0);
  ASSERT_TRUE(std::isfinite(between.errors_um.mpe));
  const SimulationResult again = sim.simulate(motion::baseline_move(), kBaselineY);
  expect_same_errors(again.errors_um, first.errors_um);
  EXPECT_EQ(again.stats.steps, first.stats.steps);
  EXPECT_EQ(again.stats.rhs_evals, first.stats.rhs_evals);
  // A fresh simulator agrees to the bit: no state leaks between moves.
  BridgeSimulator fresh(default_machine());
  expect_same_errors(first.errors_um,
                     fresh.simulate(motion::baseline_move(), kBaselineY).errors_um);
}

SimulationOptions cvode(double relative_tolerance = 1e-8, double absolute_tolerance = 1e-11) {
  SimulationOptions o;
  o.integration = Integration::kCvode;
  o.integrator.relative_tolerance = relative_tolerance;
  o.integrator.absolute_tolerance = absolute_tolerance;
  return o;
}

TEST(BridgeSimulator, CvodeTighterToleranceChangesEveryParameterByLessThanANanometre) {
  BridgeSimulator sim(default_machine(), cvode(1e-10));
  const errors::DynamicErrors a = BridgeSimulator(default_machine(), cvode())
                                      .simulate(motion::baseline_move(), kBaselineY)
                                      .errors_um;  // rtol 1e-8 (CVODE's default)
  const errors::DynamicErrors b = sim.simulate(motion::baseline_move(), kBaselineY).errors_um;
  EXPECT_NEAR(a.mpe, b.mpe, 1e-3);
  EXPECT_NEAR(a.rpe, b.rpe, 1e-3);
  EXPECT_NEAR(a.mae, b.mae, 1e-3);
  EXPECT_NEAR(a.rae, b.rae, 1e-3);
}

TEST(BridgeSimulator, ErrorGrowsWithPositioningSpeed) {
  BridgeSimulator sim(default_machine());
  motion::ProbingMove fast = motion::baseline_move();
  fast.positioning_speed = 0.100;
  const double mpe_fast = sim.simulate(fast, kBaselineY).errors_um.mpe;
  EXPECT_GT(mpe_fast, baseline_traced().errors_um.mpe);
}

TEST(BridgeSimulator, JerkLimitedMoveHasOrderedErrorsAndSamplesEveryInstant) {
  motion::ProbingMove m = motion::baseline_move();
  m.jerk = 2.0;
  BridgeSimulator sim(default_machine(), traced());
  const SimulationResult r = sim.simulate(m, kBaselineY);
  const errors::DynamicErrors& e = r.errors_um;
  ASSERT_TRUE(std::isfinite(e.mpe) && std::isfinite(e.rpe) && std::isfinite(e.mae) &&
              std::isfinite(e.rae));
  EXPECT_GT(e.mpe, 0.0);
  EXPECT_GE(e.mpe, std::fabs(e.rpe));
  EXPECT_GE(e.mae, std::fabs(e.rae));
  ASSERT_FALSE(r.trace.empty());
  EXPECT_EQ(r.trace.back().t_s, r.instants.touch);
  for (const double t : {r.instants.positioning_accel_end, r.instants.positioning_end}) {
    EXPECT_TRUE(std::any_of(
        r.trace.begin(), r.trace.end(), [t](const TraceSample& s) { return s.t_s == t; }))
        << "t=" << t;
  }
}

TEST(BridgeSimulator, StatsCountTheWork) {
  // The exponential integrator (default): equal steps of at most 0.5 ms per segment, one matrix
  // exponential per distinct step length (at most one per segment), the extrema it refined.
  const IntegratorStats& s = baseline_traced().stats;
  const double duration = baseline_traced().instants.touch;
  EXPECT_GE(s.steps, static_cast<long>(duration / 5e-4));
  EXPECT_GT(s.matrix_exponentials, 0);
  EXPECT_LE(s.matrix_exponentials, 16);
  EXPECT_GT(s.root_evals, 0);
  // CVODE: steps, right-hand sides and root evaluations.
  const IntegratorStats c = BridgeSimulator(default_machine(), cvode())
                                .simulate(motion::baseline_move(), kBaselineY)
                                .stats;
  EXPECT_GT(c.steps, 0);
  EXPECT_GE(c.rhs_evals, c.steps);
  EXPECT_GT(c.root_evals, 0);
  EXPECT_EQ(c.matrix_exponentials, 0);
}

/// Moves over the paper's Table 3 ranges and beyond (triangular positioning, jerk limits,
/// other accelerations, both beam ends), on which the two integrators are compared.
std::vector<std::pair<motion::ProbingMove, double>> comparison_moves() {
  std::vector<std::pair<motion::ProbingMove, double>> moves;
  std::uint64_t state = 20190601u;
  auto uniform = [&state](double lo, double hi) {
    state = state * 6364136223846793005ULL + 1442695040888963407ULL;
    return lo + (hi - lo) * static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  moves.push_back({motion::baseline_move(), kBaselineY});
  motion::ProbingMove triangular = motion::baseline_move();
  triangular.positioning_speed = 0.100;  // PD 40 mm < PV²/PA = 50 mm
  moves.push_back({triangular, 0.5});
  for (int i = 0; i < 10; ++i) {
    motion::ProbingMove m = motion::baseline_move();
    m.positioning_speed = uniform(0.040, 0.100);
    m.positioning_distance = uniform(0.040, 0.080);
    m.approach_speed = uniform(0.008, 0.016);
    m.approach_distance = uniform(0.005, 0.015);
    m.positioning_accel = uniform(0.1, 0.4);
    m.approach_accel = uniform(0.03, 0.12);
    if (i % 3 == 0) m.jerk = uniform(1.0, 5.0);
    moves.push_back({m, uniform(0.0, 0.5)});
  }
  return moves;
}

TEST(BridgeSimulator, ExponentialIntegratorAgreesWithCvodeToAFewNanometres) {
  // CVODE at rtol 1e-10 / atol 1e-13 m is the reference. The exponential integrator is exact in
  // the linear part; its one approximation, the Coulomb fraction as a line over each step, is
  // second order: halving the step quarters the deviation. Measured on these moves: docs/
  // machine-model.md, "Integration".
  BridgeSimulator reference(default_machine(), cvode(1e-10, 1e-13));
  BridgeSimulator exponential(default_machine());
  SimulationOptions half;
  half.exponential_max_step_s = 2.5e-4;
  BridgeSimulator finer(default_machine(), half);
  double worst = 0.0;
  double worst_finer = 0.0;
  for (const auto& [move, y] : comparison_moves()) {
    const auto r = reference.simulate(move, y).errors_um;
    const auto e = exponential.simulate(move, y).errors_um;
    const auto f = finer.simulate(move, y).errors_um;
    for (const auto member : {&errors::DynamicErrors::mpe,
                              &errors::DynamicErrors::rpe,
                              &errors::DynamicErrors::mae,
                              &errors::DynamicErrors::rae}) {
      worst = std::max(worst, std::abs(e.*member - r.*member));
      worst_finer = std::max(worst_finer, std::abs(f.*member - r.*member));
    }
  }
  std::printf(
      "exponential vs CVODE rtol 1e-10 on %zu moves: %.3g um (0.5 ms steps), %.3g um "
      "(0.25 ms)\n",
      comparison_moves().size(),
      worst,
      worst_finer);
  EXPECT_LT(worst, 2e-3) << "µm";
  EXPECT_LT(worst_finer, worst / 2.5) << "second order: " << worst << " then " << worst_finer;
}

/// Both integrators over a real CMM's envelope and random controller timing, half without
/// smoothing, on `machine` (whose capabilities must take every cycle): every move simulates on
/// both paths, and they agree. Returns the largest difference [µm].
double expect_every_envelope_move_on_both_paths(const Machine& machine, std::uint64_t seed) {
  struct Case {
    motion::ProbingMove move;
    double y, dwell_s, smoothing_s;
  };
  std::vector<Case> cases;
  motion::ProbingMove slow_long = motion::baseline_move();
  slow_long.positioning_speed = 0.005;
  slow_long.positioning_distance = 0.150;
  cases.push_back({slow_long, kBaselineY, default_machine().parameters.controller_dwell_s, 0.0});
  cases.push_back({motion::ProbingMove{0.070, 0.200, 0.040, 0.002, 0.300, 0.010, 0.0},
                   0.5,
                   0.0,
                   default_machine().parameters.controller_smoothing_s});
  detail::SplitMix64 rng{seed};
  for (int i = 0; i < 200; ++i) {
    Case c{motion::ProbingMove{rng.uniform(0.005, 0.500),
                               rng.uniform(0.050, 1.200),
                               rng.uniform(0.005, 0.300),
                               rng.uniform(0.001, 0.020),
                               rng.uniform(0.050, 1.200),
                               rng.uniform(0.0005, 0.015),
                               0.0},
           rng.uniform(0.0, 0.5),
           i % 4 == 0 ? 0.0 : rng.uniform(0.0, 1.2),
           i % 2 == 0 ? 0.0 : rng.uniform(0.0, 0.15)};
    cases.push_back(c);
  }
  std::size_t failed = 0;
  double worst = 0.0;
  BridgeSimulator exponential(machine);
  BridgeSimulator reference(machine, cvode(1e-9, 1e-12));
  for (const Case& c : cases) {
    motion::ProbingMove cycle = c.move;
    cycle.dwell = c.dwell_s;
    cycle.smoothing = c.smoothing_s;
    try {
      const auto e = exponential.simulate_cycle(cycle, c.y).errors_um;
      const auto r = reference.simulate_cycle(cycle, c.y).errors_um;
      for (const auto member : {&errors::DynamicErrors::mpe,
                                &errors::DynamicErrors::rpe,
                                &errors::DynamicErrors::mae,
                                &errors::DynamicErrors::rae}) {
        worst = std::max(worst, std::abs(e.*member - r.*member));
      }
    } catch (const Error& e) {
      ++failed;
      ADD_FAILURE() << "PV " << c.move.positioning_speed << " PD " << c.move.positioning_distance
                    << " dwell " << c.dwell_s << " smoothing " << c.smoothing_s << ": " << e.what();
    }
  }
  std::printf("%s: %zu moves, %zu failed, largest |exponential - CVODE| %.3g um\n",
              machine.name.c_str(),
              cases.size(),
              failed,
              worst);
  EXPECT_EQ(failed, 0u);
  EXPECT_LT(worst, 0.01) << "µm";
  return worst;
}

/// The shipped machine with what the compensation models do not contain: a first mode whose
/// frequency falls along the beam and a second mode.
Machine machine_with_unmodelled_mechanisms() {
  const Machine m = load_machine(CMMCOMP_DOCS_DIR "/../data/machines/variant-modes.toml");
  EXPECT_GT(m.parameters.mode_carriage_mass_share, 0.0);
  EXPECT_TRUE(has_second_mode(m.parameters));
  return m;
}

TEST(BridgeSimulator, ExponentialIntegratorSimulatesEveryMoveOfACmmEnvelopeAnyControllerTiming) {
  // An extremum kept for 0 < s < 1 inside a step once had its time t0 + s·h round onto the step's
  // start or end, and the extraction refused the two samples at one time ("invalid input"), most
  // often with smoothing_s = 0, which the machine file allows. Two reproducers, then random
  // moves: every move simulates, and agrees with CVODE.
  expect_every_envelope_move_on_both_paths(default_machine(), 38);
}

TEST(BridgeSimulator, BothIntegratorsAgreeWithASecondModeAndAFrequencyThatFallsAlongTheBeam) {
  expect_every_envelope_move_on_both_paths(machine_with_unmodelled_mechanisms(), 39);
}

/// The mean period [s] of the tip error's free ringing during the dwell of a hard-stopped move
/// (no smoothing), from the times of its maxima.
double ringing_period(const Machine& machine, double y) {
  SimulationOptions o;
  o.record_trace = true;
  o.trace_rate_hz = 20000.0;
  motion::ProbingMove cycle = motion::baseline_move();
  cycle.dwell = 0.5;
  cycle.smoothing = 0.0;
  const SimulationResult r = BridgeSimulator(machine, o).simulate_cycle(cycle, y);
  std::vector<double> maxima;
  const auto& t = r.trace;
  for (std::size_t i = 1; i + 1 < t.size(); ++i) {
    if (t[i].t_s <= r.instants.positioning_end || t[i].t_s >= r.instants.approach_start) continue;
    if (t[i].error_um > t[i - 1].error_um && t[i].error_um >= t[i + 1].error_um) {
      maxima.push_back(t[i].t_s);
    }
  }
  EXPECT_GE(maxima.size(), 4u);
  if (maxima.size() < 2) return 0.0;
  return (maxima.back() - maxima.front()) / static_cast<double>(maxima.size() - 1);
}

/// `base` without hose drag (so nothing but the structure rings at rest).
Machine without_hose(Machine m) {
  m.parameters.hose_viscous_drag_Ns_per_m = 0.0;
  m.parameters.hose_coulomb_drag_N = 0.0;
  m.parameters.hose_accel_lag_s2 = 0.0;
  return m;
}

TEST(BridgeSimulator, TheFirstModeRingsAtItsFrequencyForTheCarriagePosition) {
  Machine m = without_hose(default_machine());
  m.parameters.mode_carriage_mass_share = 0.3;
  const MachineParameters& p = m.parameters;
  ASSERT_LT(mode_frequency_at(p, p.beam_length_m), 0.95 * p.mode_frequency_hz);
  for (const double y : {0.0, p.beam_length_m}) {
    // The damped frequency is ω √(1 − ζ²): within 0.2 % of ω at ζ = 0.05.
    const double measured = 1.0 / ringing_period(m, y);
    EXPECT_NEAR(measured / mode_frequency_at(p, y), 1.0, 0.01) << "Y " << y << " m";
  }
}

TEST(BridgeSimulator, TheSecondModeRingsAtItsOwnFrequency) {
  // The first mode made negligible (its participation at the smallest physical value), the dwell
  // rings at the second mode's frequency; without the second mode it hardly rings at all.
  Machine m = without_hose(default_machine());
  m.parameters.mode_participation = 1e-3;
  m.parameters.mode2_frequency_hz = 70.0;
  m.parameters.mode2_participation = 0.3;
  const double measured = 1.0 / ringing_period(m, kBaselineY);
  EXPECT_NEAR(measured / 70.0, 1.0, 0.01);
  m.parameters.mode2_participation = 0.0;
  motion::ProbingMove cycle = motion::baseline_move();
  cycle.dwell = 0.5;
  cycle.smoothing = 0.0;
  Machine with2 = m;
  with2.parameters.mode2_participation = 0.3;
  const double without_mpe =
      std::abs(BridgeSimulator(m).simulate_cycle(cycle, kBaselineY).errors_um.mpe);
  const double with_mpe =
      std::abs(BridgeSimulator(with2).simulate_cycle(cycle, kBaselineY).errors_um.mpe);
  EXPECT_GT(with_mpe, 5.0 * without_mpe);
}

TEST(BridgeSimulator, AMachineWithoutTheNewMechanismsSimulatesAsBefore) {
  // Participation 0 switches the second mode off: its frequency, damping and shape change nothing
  // (the states are not even integrated), to the bit.
  Machine a = default_machine();
  Machine b = default_machine();
  b.parameters.mode2_frequency_hz = 150.0;
  b.parameters.mode2_damping_ratio = 0.08;
  b.parameters.mode2_shape_growth = 2.0;
  for (const bool use_cvode : {false, true}) {
    const SimulationOptions o = use_cvode ? cvode(1e-8, 1e-11) : SimulationOptions{};
    expect_same_errors(BridgeSimulator(a, o).simulate(motion::baseline_move(), 0.5).errors_um,
                       BridgeSimulator(b, o).simulate(motion::baseline_move(), 0.5).errors_um);
  }
}

TEST(BridgeSimulator, TracesOfBothIntegratorsAgree) {
  // The exponential integrator's trace (Hermite-interpolated between exact steps) against CVODE's,
  // on the same 1 kHz grid: within a few nanometres everywhere, not only at the four parameters.
  SimulationOptions o = cvode(1e-10, 1e-13);
  o.record_trace = true;
  const SimulationResult c =
      BridgeSimulator(default_machine(), o).simulate(motion::baseline_move(), kBaselineY);
  const SimulationResult& e = baseline_traced();
  std::size_t compared = 0;
  double worst = 0.0;
  std::size_t j = 0;
  for (const TraceSample& s : c.trace) {
    while (j < e.trace.size() && e.trace[j].t_s < s.t_s) ++j;
    if (j == e.trace.size()) break;
    if (e.trace[j].t_s != s.t_s) continue;
    worst = std::max(worst, std::abs(e.trace[j].error_um - s.error_um));
    ++compared;
  }
  std::printf("traces: %zu samples compared, largest difference %.3g um\n", compared, worst);
  EXPECT_GT(compared, static_cast<std::size_t>(c.instants.touch * 1000.0) - 2);
  EXPECT_LT(worst, 2e-3) << "µm";
}

TEST(BridgeSimulator, InvalidMoveIsRejectedWithAMessage) {
  BridgeSimulator sim(default_machine());
  for (const double pv : {0.0, kNaN, -0.04}) {
    motion::ProbingMove m = motion::baseline_move();
    m.positioning_speed = pv;
    const std::string msg = error_of([&] { sim.simulate(m, kBaselineY); });
    EXPECT_TRUE(contains(msg, "move")) << "PV " << pv << ": " << msg;
  }
  motion::ProbingMove m = motion::baseline_move();
  m.approach_distance = 0.0;
  EXPECT_TRUE(contains(error_of([&] { sim.simulate(m, kBaselineY); }), "move"));
}

TEST(BridgeSimulator, CarriagePositionOutOfRangeIsRejectedWithAMessage) {
  BridgeSimulator sim(default_machine());
  for (const double y : {-0.001, 3.0, kNaN}) {
    const std::string msg = error_of([&] { sim.simulate(motion::baseline_move(), y); });
    EXPECT_TRUE(contains(msg, "carriage position Y")) << "Y " << y << ": " << msg;
  }
  // Both ends of the beam are allowed.
  for (const double y : {0.0, 2.0}) {
    EXPECT_TRUE(std::isfinite(sim.simulate(motion::baseline_move(), y).errors_um.mpe)) << y;
  }
  // The simulator stays usable after rejecting input.
  expect_close_errors(sim.simulate(motion::baseline_move(), kBaselineY).errors_um,
                      baseline_traced().errors_um);
}

TEST(BridgeSimulator, NonPhysicalMachineIsAConfigError) {
  for (const auto& info : machine_parameter_table()) {
    Machine m = default_machine();
    info.set(m.parameters, info.min - std::max(1.0, std::fabs(info.min)));
    const std::string key = std::string(info.section) + "." + info.key;
    try {
      BridgeSimulator sim(m);
      ADD_FAILURE() << key << ": accepted";
    } catch (const ConfigError& e) {
      EXPECT_TRUE(contains(e.what(), key)) << e.what();
      EXPECT_TRUE(contains(e.what(), m.name)) << e.what();
    }
  }
}

TEST(BridgeSimulator, InvalidOptionsAreAConfigError) {
  SimulationOptions o;
  o.trace_rate_hz = 0.0;
  EXPECT_FALSE(o.is_valid(nullptr));
  EXPECT_THROW(BridgeSimulator(default_machine(), o), ConfigError);
  o = SimulationOptions{};
  o.integrator.relative_tolerance = -1.0;
  std::string why;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_FALSE(why.empty());
  EXPECT_THROW(BridgeSimulator(default_machine(), o), ConfigError);
  for (const double step : {0.0, -1e-3, 1.0, kNaN}) {
    o = SimulationOptions{};
    o.exponential_max_step_s = step;
    why.clear();
    EXPECT_FALSE(o.is_valid(&why)) << step;
    EXPECT_TRUE(contains(why, "exponential_max_step_s")) << why;
    EXPECT_THROW(BridgeSimulator(default_machine(), o), ConfigError);
  }
}

TEST(BridgeSimulator, CvodeFailureIsAnErrorNamingTheFlag) {
  SimulationOptions o = cvode();
  o.integrator.max_steps = 1;
  BridgeSimulator sim(default_machine(), o);
  const std::string msg = error_of([&] { sim.simulate(motion::baseline_move(), kBaselineY); });
  EXPECT_TRUE(contains(msg, "CVODE failed")) << msg;
  EXPECT_TRUE(contains(msg, "CV_TOO_MUCH_WORK")) << msg;
}

TEST(BridgeSimulator, KeepsItsMachine) {
  Machine m = default_machine();
  m.name = "bench";
  BridgeSimulator sim(m);
  EXPECT_EQ(sim.machine().name, "bench");
}

TEST(BridgeSimulator, TheControllerRefusesASettingOutsideItsCapabilities) {
  // The default machine's controller takes PV up to 500 mm/s (Tool.GoToPar.Speed) and a dwell up
  // to 2 s (no I++ property): beyond either, the twin refuses, naming the setting and its range.
  BridgeSimulator sim(default_machine());
  motion::ProbingMove fast = motion::baseline_move();
  fast.positioning_speed = 0.600;
  fast.positioning_distance = 0.300;
  try {
    sim.simulate(fast, kBaselineY);
    FAIL() << "PV 600 mm/s was simulated";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, "PV = 600 mm/s")) << msg;
    EXPECT_TRUE(contains(msg, "1 .. 500 mm/s")) << msg;
    EXPECT_TRUE(contains(msg, "Tool.GoToPar.Speed")) << msg;
    EXPECT_TRUE(contains(msg, "positioning_speed_max_mm_s")) << msg;
  }
  motion::ProbingMove long_dwell =
      controlled_move(sim.machine().parameters, motion::baseline_move());
  long_dwell.dwell = 2.5;
  try {
    sim.simulate_cycle(long_dwell, kBaselineY);
    FAIL() << "a 2.5 s dwell was simulated";
  } catch (const Error& e) {
    const std::string msg = e.what();
    EXPECT_TRUE(contains(msg, "dwell = 2.5 s")) << msg;
    EXPECT_TRUE(contains(msg, "no property")) << msg;
  }
  // Inside MoveLimits but outside the capabilities: refused by the capability check.
  motion::ProbingMove rough = long_dwell;
  rough.dwell = 0.5;
  rough.smoothing = 0.5;  // MoveLimits allow 1 s, the default machine's controller 0.2 s
  try {
    sim.simulate_cycle(rough, kBaselineY);
    FAIL() << "a 0.5 s smoothing was simulated";
  } catch (const Error& e) {
    EXPECT_TRUE(contains(e.what(), "smoothing = 0.5 s")) << e.what();
  }
}

TEST(BridgeSimulator, ACycleAtTheMachinesOwnTimingIsTheMove) {
  // simulate() is simulate_cycle() at the [controller] dwell and smoothing, bit for bit; another
  // dwell inside the capabilities changes the approach's start by exactly the difference.
  BridgeSimulator sim(default_machine());
  const motion::ProbingMove cycle =
      controlled_move(sim.machine().parameters, motion::baseline_move());
  const SimulationResult a = sim.simulate(motion::baseline_move(), kBaselineY);
  const SimulationResult b = sim.simulate_cycle(cycle, kBaselineY);
  EXPECT_EQ(a.errors_um.mpe, b.errors_um.mpe);
  EXPECT_EQ(a.errors_um.rpe, b.errors_um.rpe);
  EXPECT_EQ(a.errors_um.mae, b.errors_um.mae);
  EXPECT_EQ(a.errors_um.rae, b.errors_um.rae);
  motion::ProbingMove shorter = cycle;
  shorter.dwell = 0.3;
  const SimulationResult c = sim.simulate_cycle(shorter, kBaselineY);
  EXPECT_NEAR(c.instants.approach_start - c.instants.positioning_end, 0.3, 1e-12);
  EXPECT_NEAR(a.instants.approach_start - c.instants.approach_start, cycle.dwell - 0.3, 1e-9);
}

}  // namespace
}  // namespace cmmcomp::dynamics
