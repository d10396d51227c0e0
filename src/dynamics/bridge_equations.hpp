// SPDX-License-Identifier: MIT
/// @file The bridge model's equations (docs/machine-model.md), private to the twin: shared by the
/// CVODE path (bridge_model.cpp) and the exponential integrator (exponential_integrator.cpp), so
/// the equations are written once. Deflections are lags: positive = behind the drive.
#pragma once

#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/motion/move_profile.hpp>

namespace cmmcomp::dynamics::equations {

inline constexpr double kPi = 3.14159265358979323846;

/// State layout (docs/machine-model.md, "States").
enum : int {
  kServoError = 0,  // ε = x_scale − x_commanded [m]
  kServoRate,
  kMode,  // η: modal coordinate, the tip's lag at Y = 0 [m]
  kModeRate,
  kHoseInner,     // w: the hose link's first stage [m/s]
  kHoseVelocity,  // v_h: the hose's filtered velocity [m/s]
  kMode2,         // η₂: the second mode's coordinate, its tip lag at Y = 0 [m]
  kMode2Rate,
  kStates
};
/// The states of a machine without a second mode: the first kBaseStates.
inline constexpr int kBaseStates = kMode2;

/// Coefficients that depend only on the machine and Y, computed once per move.
struct Coefficients {
  double omega2 = 0, two_zeta_omega = 0, ff_deficit = 0, inv_mass = 0, bearing_drag = 0;
  double mode_omega2 = 0, mode_two_zeta_omega = 0;
  double participation = 0;  // Γ: modal acceleration per drive acceleration
  double drag_per_mass = 0;  // φ(Y) / m_modal: modal acceleration per N of hose drag
  double inv_tau = 0;        // 1 / τ of the hose link
  double lag_force = 0;      // N per m/s² of filtered acceleration (the delayed lag term)
  double viscous = 0, coulomb = 0, inv_coulomb_speed = 0;
  double phi = 1;  // mode shape at the tip, φ(Y)
  // The second mode (has_mode2 false: its states are not integrated, states == kBaseStates).
  bool has_mode2 = false;
  int states = kBaseStates;
  double mode2_omega2 = 0, mode2_two_zeta_omega = 0, mode2_participation = 0;
  double psi = 1;  // its shape at the tip, ψ(Y)
};

inline Coefficients coefficients(const MachineParameters& p, double y) {
  Coefficients c;
  const double omega = 2.0 * kPi * p.servo_bandwidth_hz;
  c.omega2 = omega * omega;
  c.two_zeta_omega = 2.0 * p.servo_damping_ratio * omega;
  c.ff_deficit = 1.0 - p.servo_feedforward_gain;
  c.inv_mass = 1.0 / p.servo_moving_mass_kg;
  c.bearing_drag = p.servo_bearing_drag_Ns_per_m;
  // The first mode's frequency at this Y (its modal mass grows with the carriage's share);
  // its stiffness does not change, so the drag's modal acceleration is φ ω(Y)² / k = φ / m(Y).
  const double w = 2.0 * kPi * mode_frequency_at(p, y);
  c.mode_omega2 = w * w;
  c.mode_two_zeta_omega = 2.0 * p.mode_damping_ratio * w;
  c.participation = p.mode_participation;
  c.phi = mode_shape(p, y);
  c.drag_per_mass = c.phi * c.mode_omega2 / p.mode_stiffness_N_per_m;  // φ / m_modal
  c.has_mode2 = has_second_mode(p);
  if (c.has_mode2) {
    const double w2 = 2.0 * kPi * p.mode2_frequency_hz;
    c.states = kStates;
    c.mode2_omega2 = w2 * w2;
    c.mode2_two_zeta_omega = 2.0 * p.mode2_damping_ratio * w2;
    c.mode2_participation = p.mode2_participation;
    c.psi = mode2_shape(p, y);
  }
  c.inv_tau = 1.0 / p.hose_time_constant_s;
  // The delayed lag is given as tip lag per m/s² at Y = 0; as a drag force it is k · lag.
  c.lag_force = p.mode_stiffness_N_per_m * p.hose_accel_lag_s2;
  c.viscous = p.hose_viscous_drag_Ns_per_m;
  c.coulomb = p.hose_coulomb_drag_N;
  c.inv_coulomb_speed = 1.0 / p.hose_coulomb_speed_m_per_s;
  return c;
}

/// The Coulomb drag's fraction of F_c at hose speed v_h: tanh(v_h / v₀), its one nonlinearity.
inline double coulomb_fraction(const Coefficients& c, double v_h) noexcept {
  return std::tanh(v_h * c.inv_coulomb_speed);
}

/// The hose drag on the carriage [N] from the link's state (its filtered acceleration
/// (w − v_h)/τ, its velocity v_h) and the Coulomb fraction `f` (coulomb_fraction()).
inline double hose_drag(const Coefficients& c, const double* y, double f) noexcept {
  const double v_h = y[kHoseVelocity];
  const double a_h = (y[kHoseInner] - v_h) * c.inv_tau;
  return c.lag_force * a_h + c.viscous * v_h + c.coulomb * f;
}

/// Every state derivative with the Coulomb fraction given: linear in (y, commanded velocity,
/// commanded acceleration, f), which is what the exponential integrator builds its matrix from.
/// Returns the drive acceleration a.
inline double derivatives_given_coulomb(const Coefficients& c,
                                        const motion::MotionState& cmd,
                                        const double* y,
                                        double f,
                                        double* dy) noexcept {
  const double drag = hose_drag(c, y, f);
  const double v = cmd.velocity + y[kServoRate];  // drive velocity
  // Servo: PD loop with feed-forward; the hose drag and the bearings' drag disturb it.
  const double eps_dd = -c.ff_deficit * cmd.acceleration - c.omega2 * y[kServoError] -
                        c.two_zeta_omega * y[kServoRate] - (drag + c.bearing_drag * v) * c.inv_mass;
  const double a = cmd.acceleration + eps_dd;  // drive acceleration
  dy[kServoError] = y[kServoRate];
  dy[kServoRate] = eps_dd;
  // The structural mode: base-excited by the drive's acceleration, loaded by the hose drag.
  dy[kMode] = y[kModeRate];
  dy[kModeRate] = c.participation * a + c.drag_per_mass * drag - c.mode_omega2 * y[kMode] -
                  c.mode_two_zeta_omega * y[kModeRate];
  // The hose link: two equal first-order stages (critically damped) following the drive speed.
  dy[kHoseInner] = (v - y[kHoseInner]) * c.inv_tau;
  dy[kHoseVelocity] = (y[kHoseInner] - y[kHoseVelocity]) * c.inv_tau;
  // The second mode: base-excited by the drive's acceleration only (the hose acts at the
  // carriage, which a higher mode barely moves).
  if (c.has_mode2) {
    dy[kMode2] = y[kMode2Rate];
    dy[kMode2Rate] = c.mode2_participation * a - c.mode2_omega2 * y[kMode2] -
                     c.mode2_two_zeta_omega * y[kMode2Rate];
  }
  return a;
}

/// Every state derivative (the model's right-hand side). Returns the drive acceleration a.
inline double derivatives(const Coefficients& c,
                          const motion::MotionState& cmd,
                          const double* y,
                          double* dy) noexcept {
  return derivatives_given_coulomb(c, cmd, y, coulomb_fraction(c, y[kHoseVelocity]), dy);
}

/// Raw error x_tip − x_scale [m] and its rate: the tip lags by φ(Y) η (+ ψ(Y) η₂).
inline double tip_error(const Coefficients& c, const double* y) noexcept {
  if (c.has_mode2) return -c.phi * y[kMode] - c.psi * y[kMode2];
  return -c.phi * y[kMode];
}
inline double tip_error_rate(const Coefficients& c, const double* y) noexcept {
  if (c.has_mode2) return -c.phi * y[kModeRate] - c.psi * y[kMode2Rate];
  return -c.phi * y[kModeRate];
}

}  // namespace cmmcomp::dynamics::equations
