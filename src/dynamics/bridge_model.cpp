// SPDX-License-Identifier: MIT
/// @file The bridge/carriage dynamics model and its per-move simulation.
#include <fmt/format.h>

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
enum : int {
  kServoError = 0,  // ε = x_scale − x_commanded [m]
  kServoRate,
  kYaw,  // θ [rad]
  kYawRate,
  kCarriage,  // q: carriage/ram lateral lag at Y [m]
  kCarriageRate,
  kChain,  // u: cable-chain lag [m]
  kChainRate,
  kHose,  // w: hose lag [m]
  kHoseRate,
  kStates
};
static_assert(kStates == kBridgeStateCount);

/// Coefficients that depend only on the machine and Y, computed once per move.
struct Coefficients {
  double omega2 = 0, two_zeta_omega = 0, ff_deficit = 0, inv_mass = 0, bearing_drag = 0;
  double yaw_inertia = 0, yaw_moment = 0, yaw_k = 0, yaw_c = 0, arm_idle = 0, arm_hose = 0;
  double mc = 0, cq = 0, kq = 0;
  double mk = 0, kk = 0, ck = 0, dk1 = 0, dk3 = 0;
  double mw = 0, kw = 0, cw = 0, dw1 = 0, dw3 = 0;
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
  c.arm_idle = p.idle_leg_arm_m;
  c.arm_hose = y;
  c.mc = p.carriage_mass_kg;
  c.cq = p.carriage_damping_Ns_per_m;
  // Cantilever from the drive leg: compliance = base + Y³ / (3 EI).
  c.kq = 1.0 / (p.beam_base_compliance_m_per_N + y * y * y / (3.0 * p.beam_bending_EI_Nm2));
  c.mk = p.chain_mass_kg;
  c.kk = p.chain_stiffness_N_per_m;
  c.ck = p.chain_damping_Ns_per_m;
  c.dk1 = p.chain_drag_linear_Ns_per_m;
  c.dk3 = p.chain_drag_cubic_Ns3_per_m3;
  c.mw = p.hose_mass_kg;
  c.kw = p.hose_stiffness_N_per_m;
  c.cw = p.hose_damping_Ns_per_m;
  c.dw1 = p.hose_drag_linear_Ns_per_m;
  c.dw3 = p.hose_drag_cubic_Ns3_per_m3;
  c.tip_arm = y + p.scale_offset_m;
  return c;
}

/// What the right-hand side needs: the coefficients and the commanded segment in force.
struct Forcing {
  Coefficients c;
  motion::Segment segment;
};

/// Drive acceleration and every state derivative. Returns the drive acceleration a_s.
double derivatives(const Coefficients& c,
                   const motion::MotionState& cmd,
                   const double* y,
                   double* dy) noexcept {
  const double v = cmd.velocity + y[kServoRate];  // drive velocity
  const double chain_pull = c.kk * y[kChain] + c.ck * y[kChainRate];
  const double hose_pull = c.kw * y[kHose] + c.cw * y[kHoseRate];
  // Servo: PD loop with feed-forward; every force on the bridge disturbs it.
  const double eps_dd = -c.ff_deficit * cmd.acceleration - c.omega2 * y[kServoError] -
                        c.two_zeta_omega * y[kServoRate] -
                        (chain_pull + hose_pull + c.bearing_drag * v) * c.inv_mass;
  const double a = cmd.acceleration + eps_dd;  // drive acceleration
  dy[kServoError] = y[kServoRate];
  dy[kServoRate] = eps_dd;
  // Appendages: base-excited by the bridge, dragged by the floor/trough.
  const double v3 = v * v * v;
  dy[kChain] = y[kChainRate];
  dy[kChainRate] =
      (c.mk * a + c.dk1 * v + c.dk3 * v3 - c.ck * y[kChainRate] - c.kk * y[kChain]) / c.mk;
  dy[kHose] = y[kHoseRate];
  dy[kHoseRate] =
      (c.mw * a + c.dw1 * v + c.dw3 * v3 - c.cw * y[kHoseRate] - c.kw * y[kHose]) / c.mw;
  // Bridge yaw about the drive leg: inertia plus the appendages' pull at their arms.
  dy[kYaw] = y[kYawRate];
  dy[kYawRate] = (c.yaw_moment * a + c.arm_idle * chain_pull + c.arm_hose * hose_pull -
                  c.yaw_c * y[kYawRate] - c.yaw_k * y[kYaw]) /
                 c.yaw_inertia;
  // Carriage and ram on the beam: inertia plus the hose pull.
  dy[kCarriage] = y[kCarriageRate];
  dy[kCarriageRate] = (c.mc * a + hose_pull - c.cq * y[kCarriageRate] - c.kq * y[kCarriage]) / c.mc;
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
    // Output grid: multiples of dt inside the segment, then the segment end (a kink).
    double next = (std::floor(seg.start_time / dt + 1e-6) + 1.0) * dt;
    if (next <= seg.start_time + 1e-6 * dt) next += dt;
    double t = seg.start_time;
    while (t < t_end) {
      const double target = next < t_end ? next : t_end;
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
