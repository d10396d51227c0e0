// SPDX-License-Identifier: MIT
/// @file The bridge/carriage dynamics model and its per-move simulation.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/exceptions.hpp>
#include <string>

#include "bridge_equations.hpp"
#include "exponential_integrator.hpp"

namespace cmmcomp::dynamics {
namespace {

constexpr double kMaxCarriageY = 2.0;  // [m]

using namespace equations;
static_assert(kStates == kBridgeStateCount);

/// Per-state absolute tolerances such that each state's share of the tip error stays below
/// `error_tol` [m]: states with a small lever on the tip may be integrated more loosely.
std::array<double, kStates> state_tolerances(const Coefficients& c, double error_tol) {
  std::array<double, kStates> a{};
  const double mode_omega = std::sqrt(c.mode_omega2);
  // Tip lag per N of hose drag (static), and per m/s of hose velocity through the steepest
  // drag slope (the Coulomb term's at rest).
  const double per_newton = c.phi * c.drag_per_mass / c.mode_omega2;
  const double slope = c.viscous + c.coulomb * c.inv_coulomb_speed + c.lag_force * c.inv_tau;
  // The servo error moves scale and tip together; it reaches the tip only through the drive's
  // acceleration, ω_s² ε of it per metre.
  a[kServoError] = error_tol * c.mode_omega2 / (c.phi * c.participation * c.omega2 + 1e-300);
  a[kServoRate] = a[kServoError] * std::sqrt(c.omega2);
  a[kMode] = error_tol / c.phi;
  a[kModeRate] = a[kMode] * mode_omega;
  // Without hose drag the link's states do not reach the tip: any finite tolerance will do.
  const double hose_lever = per_newton * slope;
  a[kHoseInner] = hose_lever > 0.0 ? error_tol / hose_lever : 1.0;
  a[kHoseVelocity] = a[kHoseInner];
  if (c.has_mode2) {
    a[kMode2] = error_tol / c.psi;
    a[kMode2Rate] = a[kMode2] * std::sqrt(c.mode2_omega2);
  }
  return a;
}

/// What the right-hand side needs: the coefficients and the commanded segment in force.
struct Forcing {
  Coefficients c;
  motion::Segment segment;
};

int rhs(double t, const double* y, double* dy, void* user) noexcept {
  const Forcing& f = *static_cast<const Forcing*>(user);
  derivatives(f.c, f.segment.at(t - f.segment.start_time), y, dy);
  return 0;
}

int roots(double /*t*/, const double* y, double* g, void* user) noexcept {
  const Forcing& f = *static_cast<const Forcing*>(user);
  g[0] = tip_error_rate(f.c, y);
  return 0;
}

void accumulate(IntegratorStats& total, const IntegratorStats& s) {
  total.steps += s.steps;
  total.rhs_evals += s.rhs_evals;
  total.root_evals += s.root_evals;
  total.error_test_fails += s.error_test_fails;
}

}  // namespace

bool SimulationOptions::is_valid(std::string* why) const {
  if (!integrator.is_valid(why)) return false;
  if (!(exponential_max_step_s >= 1e-6 && exponential_max_step_s <= 0.1)) {
    if (why != nullptr) *why = "exponential_max_step_s must be in [1e-6, 0.1] s";
    return false;
  }
  if (!(trace_rate_hz >= 1.0 && trace_rate_hz <= 1e6)) {
    if (why != nullptr) *why = "trace_rate_hz must be in [1, 1e6]";
    return false;
  }
  return true;
}

struct BridgeSimulator::Impl {
  Machine machine;
  SimulationOptions options;
  Forcing forcing;
  Integrator integrator;

  Impl(const Machine& m, const SimulationOptions& o)
      : machine(m),
        options(o),
        integrator(o.integrator,
                   &rhs,
                   &forcing,
                   has_second_mode(m.parameters) ? kStates : kBaseStates,
                   &roots,
                   1) {}
};

BridgeSimulator::BridgeSimulator(const Machine& machine, const SimulationOptions& options) {
  std::string why;
  if (!is_physical(machine.parameters, &why)) {
    throw ConfigError("machine '" + machine.name + "': " + why);
  }
  if (!options.is_valid(&why)) throw ConfigError("simulation options: " + why);
  impl_ = std::make_unique<Impl>(machine, options);
}

BridgeSimulator::~BridgeSimulator() = default;

const Machine& BridgeSimulator::machine() const noexcept { return impl_->machine; }

SimulationResult BridgeSimulator::simulate(const motion::ProbingMove& move, double carriage_y_m) {
  // The machine's own dwell and smoothing are its controller's setting: only the motion settings
  // are checked against the capabilities.
  const Machine& machine = impl_->machine;
  const motion::ProbingMove cycle = controlled_move(machine.parameters, move);
  motion::ControllerCapabilities caps = machine.capabilities;
  caps[motion::Setting::kDwell] = {cycle.dwell, cycle.dwell};
  caps[motion::Setting::kSmoothing] = {cycle.smoothing, cycle.smoothing};
  if (motion::first_invalid_parameter(cycle).label == nullptr) {
    const std::string problem = capability_problem(machine.name, caps, cycle);
    if (!problem.empty()) throw Error(problem);
  }
  return run(cycle, carriage_y_m);
}

SimulationResult BridgeSimulator::simulate_cycle(const motion::ProbingMove& cycle,
                                                 double carriage_y_m) {
  if (motion::first_invalid_parameter(cycle).label == nullptr) {
    const std::string problem = capability_problem(impl_->machine, cycle);
    if (!problem.empty()) throw Error(problem);
  }
  return run(cycle, carriage_y_m);
}

SimulationResult BridgeSimulator::run(const motion::ProbingMove& cycle, double carriage_y_m) {
  if (!(carriage_y_m >= 0.0 && carriage_y_m <= kMaxCarriageY)) {
    throw Error(fmt::format(
        "carriage position Y = {} m is outside 0 .. {} m", carriage_y_m, kMaxCarriageY));
  }
  motion::MoveProfile profile;
  const motion::ProbingMove& controlled = cycle;
  const Status planned = motion::MoveProfile::plan(controlled, profile);
  if (!ok(planned)) {
    const motion::MoveParameterProblem bad = motion::first_invalid_parameter(controlled);
    if (bad.label != nullptr) {
      throw Error(fmt::format("cannot plan the move: {} = {:g} {} is outside {:g} .. {:g} {}",
                              bad.label,
                              bad.value,
                              bad.unit,
                              bad.min,
                              bad.max,
                              bad.unit));
    }
    throw Error(std::string("cannot plan the move: ") + to_string(planned));
  }
  Impl& m = *impl_;
  m.forcing.c = coefficients(m.machine.parameters, carriage_y_m);
  const Coefficients& c = m.forcing.c;
  const std::array<double, kStates> atol =
      state_tolerances(c, m.options.integrator.absolute_tolerance);
  if (!ok(m.integrator.set_absolute_tolerances(atol.data()))) {
    throw Error("CVODE rejected the state tolerances (non-physical machine?)");
  }

  SimulationResult result;
  result.instants = profile.instants();
  std::vector<double> times;
  std::vector<double> errs;
  const double touch = profile.instants().touch;
  const double dt = 1.0 / m.options.trace_rate_hz;
  times.reserve(static_cast<std::size_t>(touch / dt) + 64);
  errs.reserve(times.capacity());

  std::array<double, kStates> y{};  // at rest, undeformed
  auto record = [&](double t, const motion::MotionState& cmd) {
    times.push_back(t);
    errs.push_back(tip_error(c, y.data()) * 1e6);
    if (m.options.record_trace) {
      std::array<double, kStates> dy{};
      const double a = derivatives(c, cmd, y.data(), dy.data());
      TraceSample s;
      s.t_s = t;
      s.commanded_mm = cmd.position * 1e3;
      s.scale_mm = (cmd.position + y[kServoError]) * 1e3;
      s.tip_mm = s.scale_mm + tip_error(c, y.data()) * 1e3;
      s.error_um = errs.back();
      s.velocity_mm_s = (cmd.velocity + y[kServoRate]) * 1e3;
      s.acceleration_mm_s2 = a * 1e3;
      result.trace.push_back(s);
    }
  };
  record(0.0, profile.sample(0.0));

  if (m.options.integration == Integration::kExponential) {
    ExponentialIntegrator stepper(c, m.options.exponential_max_step_s);
    const double trace_dt = m.options.record_trace ? dt : 0.0;
    for (int k = 0; k < profile.segment_count(); ++k) {
      const motion::Segment& seg = profile.segment(k);
      stepper.advance(seg, y.data(), trace_dt, [&](double t, const double* state) {
        if (state != y.data()) std::copy(state, state + c.states, y.begin());
        record(t, seg.at(t - seg.start_time));
      });
    }
    result.stats.steps = stepper.steps();
    result.stats.matrix_exponentials = stepper.matrix_exponentials();
    result.stats.root_evals = stepper.extrema();
  } else {
    for (int k = 0; k < profile.segment_count(); ++k) {
      const motion::Segment& seg = profile.segment(k);
      m.forcing.segment = seg;
      const double t_end = seg.end_time();
      if (!ok(m.integrator.reset(seg.start_time, y.data())) ||
          !ok(m.integrator.set_stop_time(t_end))) {
        throw Error(fmt::format("CVODE could not restart at t = {} s ({})",
                                seg.start_time,
                                m.integrator.last_flag_name()));
      }
      // Output grid (only for a recorded trace): multiples of dt inside the segment. The
      // parameters need no grid: the kinks are the phase instants and the root function stops
      // at every extremum of the error.
      double next = (std::floor(seg.start_time / dt + 1e-6) + 1.0) * dt;
      if (next <= seg.start_time + 1e-6 * dt) next += dt;
      double t = seg.start_time;
      while (t < t_end) {
        const double target = (m.options.record_trace && next < t_end) ? next : t_end;
        bool root = false;
        double reached = t;
        if (!ok(m.integrator.advance_to(target, y.data(), &reached, &root))) {
          throw Error(fmt::format("CVODE failed at t = {:.6f} s of a {:.6f} s move: {}",
                                  reached,
                                  touch,
                                  m.integrator.last_flag_name()));
        }
        if (!(reached > t)) {
          // Root exactly at the restart point: nothing new to record.
          if (root) continue;
          throw Error(fmt::format("CVODE made no progress at t = {:.6f} s", t));
        }
        t = reached;
        record(t, seg.at(t - seg.start_time));
        if (!root && t >= target) next += dt;
      }
      accumulate(result.stats, m.integrator.stats());
    }
  }

  const errors::TraceView view{times.data(), errs.data(), times.size()};
  const Status extracted =
      errors::extract_dynamic_errors(view, result.instants, +1, result.errors_um);
  if (!ok(extracted)) {
    throw Error(std::string("cannot extract the dynamic errors: ") + to_string(extracted));
  }
  return result;
}

std::string format_move_json(const errors::DynamicErrors& e) {
  return fmt::format(
      "{{\"mpe_um\": {:.6f}, \"rpe_um\": {:.6f}, \"mae_um\": {:.6f}, \"rae_um\": {:.6f}}}",
      e.mpe,
      e.rpe,
      e.mae,
      e.rae);
}

std::string format_move_report(const Machine& machine,
                               const SimulationResult& r,
                               const errors::DynamicErrors& e,
                               bool cvode) {
  std::string out = fmt::format("machine: {}\n", machine.name);
  out += fmt::format("MPE {:9.3f} um\nRPE {:9.3f} um\nMAE {:9.3f} um\nRAE {:9.3f} um\n",
                     e.mpe,
                     e.rpe,
                     e.mae,
                     e.rae);
  out += fmt::format(
      "(RPE at the deceleration start, {:.4f} s; MAE from the approach start after the {:.3f} s "
      "dwell, {:.4f} s; RAE at the touch, {:.4f} s)\n",
      r.instants.positioning_decel_start,
      r.instants.approach_start - r.instants.positioning_end,
      r.instants.approach_start,
      r.instants.touch);
  if (cvode) {
    out += fmt::format(
        "(CVODE: {} steps, {} right-hand-side evaluations)\n", r.stats.steps, r.stats.rhs_evals);
  } else {
    out += fmt::format("(exponential integrator: {} steps, {} matrix exponentials)\n",
                       r.stats.steps,
                       r.stats.matrix_exponentials);
  }
  return out;
}

}  // namespace cmmcomp::dynamics
