// SPDX-License-Identifier: MIT
/// @file The digital twin: simulates one probing move on a machine and reports its dynamic errors.
///
/// Offline code (allocates, throws). The equations are in docs/machine-model.md. By default they
/// are integrated exactly in their linear part (Integration::kExponential: a matrix exponential
/// per step, the Coulomb drag's tanh as a line over each step, extrema of the error refined on
/// a cubic interpolant); SUNDIALS CVODE (Integration::kCvode: Adams–Moulton with fixed-point
/// iteration, see default_integrator_options(); BDF with a dense linear solver when
/// IntegratorOptions::bdf; a root function on de/dt) is the reference it is tested against.
/// Both start from all states zero (at rest, undeformed) and stop at every kink of the commanded
/// profile, so the phase instants are samples of the trace.
#pragma once

#include <cmmcomp/dynamics/integrator.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <memory>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// The integrator settings the bridge model uses by default.
inline IntegratorOptions default_integrator_options() {
  IntegratorOptions o;
  o.relative_tolerance = 1e-8;
  o.absolute_tolerance = 1e-11;
  // The model is not stiff (its fastest pole, the servo, is 30 Hz; the lightly damped mode sets
  // the step): Adams–Moulton with fixed-point iteration takes fewer, cheaper steps than BDF.
  o.bdf = false;
  return o;
}

/// How the twin integrates the model (docs/machine-model.md, "Integration").
enum class Integration {
  /// Default: the linear part exactly (matrix exponential per step), the Coulomb drag's tanh as
  /// a line over each step of at most `exponential_max_step_s`. About 6x faster than CVODE.
  kExponential,
  /// SUNDIALS CVODE with `integrator`'s settings: the reference the exponential path is tested
  /// against.
  kCvode,
};

/// How to simulate.
struct SimulationOptions {
  Integration integration = Integration::kExponential;
  /// Longest step of the exponential integrator [s], in [1e-6, 0.1]. At 0.5 ms the four
  /// parameters are within 4.1e-4 µm of CVODE at rtol 1e-10 on 12 test moves (1.8e-4 µm on the
  /// baseline), in 0.39 ms a baseline move; halving it quarters the deviation
  /// (docs/machine-model.md, "Integration").
  double exponential_max_step_s = 5e-4;
  /// CVODE settings. Here `absolute_tolerance` bounds each state's share of the tip error [m]
  /// (states get tolerances scaled by their lever on the tip). Defaults: rtol 1e-8 and 1e-11 m
  /// (1e-5 µm). Measured on the baseline move (bench_simulation
  /// --benchmark_filter=Tolerance): the four parameters are then within 4.7e-4 µm of an
  /// rtol 1e-10 / atol 1e-13 m solution; at rtol 1e-7 / atol 1e-10 m within 1.4e-3 µm.
  IntegratorOptions integrator = default_integrator_options();
  bool record_trace = false;      ///< keep the sampled trace in the result
  double trace_rate_hz = 1000.0;  ///< trace samples per second (extrema and kinks always added)

  bool is_valid(std::string* why) const;
};

/// One sample of a simulated move. Positions from the move start along the axis.
struct TraceSample {
  double t_s = 0;                 ///< time [s]
  double commanded_mm = 0;        ///< commanded position [mm]
  double scale_mm = 0;            ///< X scale reading (drive side) [mm]
  double tip_mm = 0;              ///< probe tip [mm]
  double error_um = 0;            ///< e = (tip − scale)·d [µm]
  double velocity_mm_s = 0;       ///< drive velocity [mm/s]
  double acceleration_mm_s2 = 0;  ///< drive acceleration [mm/s²]
};

/// The outcome of one simulated move.
struct SimulationResult {
  errors::DynamicErrors errors_um;  ///< MPE, RPE, MAE, RAE [µm], noiseless
  motion::PhaseInstants instants;   ///< of the planned profile
  std::vector<TraceSample> trace;   ///< empty unless SimulationOptions::record_trace
  IntegratorStats stats;            ///< the integrator's work for this move
};

/// Simulates moves on one machine. Not thread-safe: use one per thread (construction is cheap).
class BridgeSimulator {
 public:
  /// Setup only. Throws ConfigError when the machine is not physical or options are invalid.
  explicit BridgeSimulator(const Machine& machine, const SimulationOptions& options = {});
  ~BridgeSimulator();
  BridgeSimulator(const BridgeSimulator&) = delete;
  BridgeSimulator& operator=(const BridgeSimulator&) = delete;

  /// Simulates `move` with the carriage at `carriage_y_m` [m] (0 = drive side, up to 2 m). The
  /// machine's controller runs it: its dwell and smoothing replace the move's
  /// (controlled_move()), and `instants` are those of the controlled profile.
  /// Throws Error for an invalid move or Y (message says which), for a setting outside the
  /// machine's capabilities (capability_problem()), or when CVODE fails (message carries CVODE's
  /// flag and the time reached).
  SimulationResult simulate(const motion::ProbingMove& move, double carriage_y_m);
  /// The same for a whole probing cycle whose controller settings are chosen: the cycle's own
  /// dwell and smoothing, which the machine's capabilities must allow, replace the machine's.
  SimulationResult simulate_cycle(const motion::ProbingMove& cycle, double carriage_y_m);

  const Machine& machine() const noexcept;

 private:
  /// Plans and integrates `cycle` as given (no capability check).
  SimulationResult run(const motion::ProbingMove& cycle, double carriage_y_m);
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Number of states in the model (for documentation and tests): 6, and 8 for a machine with a
/// second structural mode.
inline constexpr int kBridgeStateCount = 8;

/// One simulated move as cmmcomp-sim move prints it: the machine, the four parameters `e` [µm]
/// (with noise, when added), the instants they were taken at, and the integrator's effort.
std::string format_move_report(const Machine& machine,
                               const SimulationResult& result,
                               const errors::DynamicErrors& e,
                               bool cvode);
/// The four parameters as one JSON object line: {"mpe_um": …, "rpe_um": …, "mae_um": …,
/// "rae_um": …} (6 decimals).
std::string format_move_json(const errors::DynamicErrors& e);

}  // namespace cmmcomp::dynamics
