// SPDX-License-Identifier: MIT
/// @file The bridge/carriage dynamics model and its per-move simulation.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/error.hpp>
#include <string>

namespace cmmcomp::dynamics {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kMaxCarriageY = 2.0;  // [m]

// State layout (docs/machine-model.md). Deflections are lags: positive = behind the drive.
constexpr int kLoads = MachineParameters::kDragLoads;
enum : int {
  kServoError = 0,  // ε = x_scale − x_commanded [m]
  kServoRate,
  kYaw,  // θ [rad]
  kYawRate,
  kCarriage,  // q: carriage/ram lateral lag at Y [m]
  kCarriageRate,
  kFirstLoad,  // u_k, u̇_k: drag-load coordinates [m], k = 0..2
  kStates = kFirstLoad + 2 * kLoads
};
static_assert(kStates == kBridgeStateCount);

/// Coefficients that depend only on the machine and Y, computed once per move.
struct Coefficients {
  double omega2 = 0, two_zeta_omega = 0, ff_deficit = 0, inv_mass = 0, bearing_drag = 0;
  double yaw_inertia = 0, yaw_moment = 0, yaw_k = 0, yaw_c = 0, load_arm = 0;
  double mc = 0, cq = 0, kq = 0;
  std::array<MachineParameters::DragLoad, kLoads> load{};
  double tip_arm = 0;  // lever from the scale to the tip [m]
};

Coefficients coefficients(const MachineParameters& p, double y) {
  Coefficients c;
  const double omega = 2.0 * kPi * p.servo_bandwidth_hz;
  c.omega2 = omega * omega;
  c.two_zeta_omega = 2.0 * p.servo_damping_ratio * omega;
  c.ff_deficit = 1.0 - p.servo_feedforward_gain;
  c.inv_mass = 1.0 / p.servo_moving_mass_kg;
  c.bearing_drag = p.servo_bearing_drag_Ns_per_m;
  c.yaw_inertia = p.yaw_inertia_kgm2 + p.carriage_mass_kg * y * y;
  c.yaw_moment = p.yaw_static_moment_kgm + p.carriage_mass_kg * y;
  c.yaw_k = p.yaw_stiffness_Nm_per_rad;
  c.yaw_c = p.yaw_damping_Nms_per_rad;
  c.load_arm = y;  // the loads pull at the carriage
  c.mc = p.carriage_mass_kg;
  c.cq = p.carriage_damping_Ns_per_m;
  // Cantilever from the drive leg: compliance = base + Y³ / (3 EI).
  c.kq = 1.0 / (p.beam_base_compliance_m_per_N + y * y * y / (3.0 * p.beam_bending_EI_Nm2));
  for (int k = 0; k < kLoads; ++k) c.load[static_cast<std::size_t>(k)] = p.load[k];
  c.tip_arm = y + p.scale_offset_m;
  return c;
}

/// Per-state absolute tolerances such that each state's share of the tip error stays below
/// `error_tol` [m]: states with a small lever on the tip may be integrated more loosely.
std::array<double, kStates> state_tolerances(const Coefficients& c, double error_tol) {
  std::array<double, kStates> a{};
  const double compliance = 1.0 / c.kq;
  const double omega_servo = std::sqrt(c.omega2);
  const double servo_gain = (compliance * c.mc + c.tip_arm * c.yaw_moment / c.yaw_k) * c.omega2;
  a[kServoError] = error_tol / servo_gain;
  a[kServoRate] = a[kServoError] * omega_servo;
  a[kYaw] = error_tol / std::max(c.tip_arm, 1e-3);
  a[kYawRate] = a[kYaw] * std::sqrt(c.yaw_k / c.yaw_inertia);
  a[kCarriage] = error_tol;
  a[kCarriageRate] = error_tol * std::sqrt(c.kq / c.mc);
  for (int k = 0; k < kLoads; ++k) {
    const auto& l = c.load[static_cast<std::size_t>(k)];
    const int i = kFirstLoad + 2 * k;
    a[static_cast<std::size_t>(i)] = error_tol / (compliance * l.stiffness_N_per_m);
    a[static_cast<std::size_t>(i + 1)] =
        std::min(error_tol / (compliance * l.damping_Ns_per_m),
                 a[static_cast<std::size_t>(i)] * std::sqrt(l.stiffness_N_per_m / l.mass_kg));
  }
  return a;
}

/// What the right-hand side needs: the coefficients and the commanded segment in force.
struct Forcing {
  Coefficients c;
  motion::Segment segment;
};

/// Every state derivative. Returns the drive acceleration a_s.
double derivatives(const Coefficients& c,
                   const motion::MotionState& cmd,
                   const double* y,
                   double* dy) noexcept {
  const double v = cmd.velocity + y[kServoRate];  // drive velocity
  double pull = 0.0;                              // the loads' pull on the carriage [N]
  for (int k = 0; k < kLoads; ++k) {
    const auto& l = c.load[static_cast<std::size_t>(k)];
    pull += l.stiffness_N_per_m * y[kFirstLoad + 2 * k] +
            l.damping_Ns_per_m * y[kFirstLoad + 2 * k + 1];
  }
  // Servo: PD loop with feed-forward; every force on the bridge disturbs it.
  const double eps_dd = -c.ff_deficit * cmd.acceleration - c.omega2 * y[kServoError] -
                        c.two_zeta_omega * y[kServoRate] - (pull + c.bearing_drag * v) * c.inv_mass;
  const double a = cmd.acceleration + eps_dd;  // drive acceleration
  dy[kServoError] = y[kServoRate];
  dy[kServoRate] = eps_dd;
  // Drag loads: base-excited by the bridge, driven by a drag force that grows with speed.
  const double v3 = v * v * v;
  for (int k = 0; k < kLoads; ++k) {
    const auto& l = c.load[static_cast<std::size_t>(k)];
    const int i = kFirstLoad + 2 * k;
    dy[i] = y[i + 1];
    dy[i + 1] = (l.mass_kg * a + l.drag_linear_Ns_per_m * v + l.drag_cubic_Ns3_per_m3 * v3 -
                 l.damping_Ns_per_m * y[i + 1] - l.stiffness_N_per_m * y[i]) /
                l.mass_kg;
  }
  // Bridge yaw about the drive leg: inertia plus the loads' pull at the carriage.
  dy[kYaw] = y[kYawRate];
  dy[kYawRate] =
      (c.yaw_moment * a + c.load_arm * pull - c.yaw_c * y[kYawRate] - c.yaw_k * y[kYaw]) /
      c.yaw_inertia;
  // Carriage and ram on the beam: inertia plus the loads' pull.
  dy[kCarriage] = y[kCarriageRate];
  dy[kCarriageRate] = (c.mc * a + pull - c.cq * y[kCarriageRate] - c.kq * y[kCarriage]) / c.mc;
  return a;
}

/// Raw error x_tip − x_scale [m] and its rate.
double tip_error(const Coefficients& c, const double* y) noexcept {
  return -(c.tip_arm * y[kYaw] + y[kCarriage]);
}
double tip_error_rate(const Coefficients& c, const double* y) noexcept {
  return -(c.tip_arm * y[kYawRate] + y[kCarriageRate]);
}

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
      : machine(m), options(o), integrator(o.integrator, &rhs, &forcing, kStates, &roots, 1) {}
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
  if (!(carriage_y_m >= 0.0 && carriage_y_m <= kMaxCarriageY)) {
    throw Error(fmt::format(
        "carriage position Y = {} m is outside 0 .. {} m", carriage_y_m, kMaxCarriageY));
  }
  motion::MoveProfile profile;
  const Status planned = motion::MoveProfile::plan(move, profile);
  if (!ok(planned)) {
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

  const errors::TraceView view{times.data(), errs.data(), times.size()};
  const Status extracted =
      errors::extract_dynamic_errors(view, result.instants, +1, result.errors_um);
  if (!ok(extracted)) {
    throw Error(std::string("cannot extract the dynamic errors: ") + to_string(extracted));
  }
  return result;
}

}  // namespace cmmcomp::dynamics
