// SPDX-License-Identifier: MIT
/// @file The physical parameters of a moving-bridge CMM's X axis, and its machine file.
///
/// The lumped model (docs/machine-model.md) has four parts, each with physical parameters:
///  - servo: the drive follows the commanded profile through a position/velocity loop with
///    acceleration feed-forward, disturbed by the hose drag; its error moves scale and tip
///    together, so it never enters tip − scale;
///  - structure: the dominant X-direction mode of bridge and ram (10–50 Hz, lightly damped),
///    excited by the drive's acceleration and by the hose drag at the carriage; its shape at the
///    tip grows with the carriage position Y (the beam is a cantilever from the drive leg), and
///    its frequency may fall as the carriage's mass moves out along it; optionally a second,
///    higher mode excited by the drive's acceleration (format 4; absent when its participation
///    is 0). The compensation models do not contain these two (docs/machine-model.md, "What the
///    models do not know"): they make a twin that is not the model's own equations;
///  - hose: the hose and cable-carrier drag (viscous plus Coulomb), reaching the carriage through
///    a critically damped link, so it builds up and relaxes over its time constant;
///  - controller: the settings that shape every move (a settling dwell at the pre-hit point, a
///    command smoothing).
/// Machine files are TOML (docs/machine-file.md); every key carries its unit in its name.
#pragma once

#include <cmath>
#include <cmmcomp/dynamics/parameter_table.hpp>
#include <cmmcomp/motion/controller_capabilities.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// All physical parameters, SI units. Values of a default-constructed struct are placeholders;
/// use default_machine() or load_machine().
struct MachineParameters {
  // servo
  double servo_bandwidth_hz = 30.0;          ///< closed-loop position bandwidth [Hz]
  double servo_damping_ratio = 0.7;          ///< closed-loop damping ratio [-]
  double servo_feedforward_gain = 1.0;       ///< acceleration feed-forward gain [-]
  double servo_moving_mass_kg = 400.0;       ///< mass the X drive accelerates [kg]
  double servo_bearing_drag_Ns_per_m = 0.1;  ///< viscous drag of the air bearings [N s/m]
  // structure: the dominant X mode of bridge and ram
  double mode_frequency_hz = 22.0;        ///< natural frequency [Hz]
  double mode_damping_ratio = 0.05;       ///< modal damping ratio [-]
  double mode_stiffness_N_per_m = 3.3e6;  ///< modal stiffness at the tip for Y = 0 [N/m]
  double mode_participation = 0.5;        ///< inertial participation factor Γ [-]
  double mode_shape_growth = 0.5;         ///< φ(L) − 1: mode shape at the far end [-]
  double beam_length_m = 0.5;             ///< carriage travel L along the beam [m]
  /// μ: the carriage and ram's share of the mode's modal mass at Y = 0 [-]. The modal mass grows
  /// as 1 + μ (φ(Y)² − 1) when the carriage moves out, so f₁(Y) = f₁ / √(1 + μ (φ(Y)² − 1)).
  double mode_carriage_mass_share = 0.0;
  // the second structural mode (absent when its participation is 0)
  double mode2_frequency_hz = 60.0;   ///< natural frequency [Hz]
  double mode2_damping_ratio = 0.03;  ///< modal damping ratio [-]
  double mode2_participation = 0.0;   ///< inertial participation factor Γ₂ [-]; 0 = no mode
  double mode2_shape_growth = 0.0;  ///< ψ(L) − 1: its shape at the tip, ψ(Y) = 1 + g₂ (Y/L)³
  // hose and cable carrier
  double hose_time_constant_s = 0.1;          ///< critically damped link time constant [s]
  double hose_viscous_drag_Ns_per_m = 200.0;  ///< viscous drag [N s/m]
  double hose_coulomb_drag_N = 10.0;          ///< Coulomb drag [N]
  double hose_coulomb_speed_m_per_s = 5e-4;   ///< speed over which the Coulomb drag builds [m/s]
  double hose_accel_lag_s2 = 5e-5;            ///< delayed tip lag per acceleration [m/(m/s²)]
  // controller
  double controller_dwell_s = 0.8;       ///< settling dwell at the pre-hit point [s]
  double controller_smoothing_s = 0.04;  ///< command smoothing (moving average) [s]
};

/// Shape of the structural mode at the tip with the carriage at `y` [m], normalised to 1 at
/// Y = 0: φ(Y) = 1 + g (Y/L)³ (the beam bends as a cantilever from the drive leg).
inline double mode_shape(const MachineParameters& p, double y) noexcept {
  const double x = y / p.beam_length_m;
  return 1.0 + p.mode_shape_growth * x * x * x;
}

/// The first mode's natural frequency [Hz] with the carriage at `y` [m]: its modal mass grows by
/// the carriage's share μ times φ(Y)² − 1, its stiffness stays.
inline double mode_frequency_at(const MachineParameters& p, double y) noexcept {
  const double phi = mode_shape(p, y);
  return p.mode_frequency_hz / std::sqrt(1.0 + p.mode_carriage_mass_share * (phi * phi - 1.0));
}

/// Shape of the second mode at the tip, normalised to 1 at Y = 0: ψ(Y) = 1 + g₂ (Y/L)³.
inline double mode2_shape(const MachineParameters& p, double y) noexcept {
  const double x = y / p.beam_length_m;
  return 1.0 + p.mode2_shape_growth * x * x * x;
}

/// True when the machine has a second structural mode (its participation is not 0).
inline bool has_second_mode(const MachineParameters& p) noexcept {
  return p.mode2_participation != 0.0;
}

/// Derived modal figures of a machine, for `cmmcomp-sim machine` and the docs.
struct ModalSummary {
  double servo_frequency_hz = 0, servo_damping_ratio = 0;
  double mode_frequency_hz = 0, mode_damping_ratio = 0, mode_mass_kg = 0;
  double mode_frequency_at_end_hz = 0;  ///< the first mode's frequency with the carriage at Y = L
  double mode2_frequency_hz = 0;        ///< 0 when the machine has no second mode
  double hose_frequency_hz = 0, hose_damping_ratio = 1.0;  ///< the link: 1/(2π τ), critical
  double smoothing_periods = 0;  ///< command smoothing in periods of the structural mode
  /// Static tip lag per m/s² of acceleration and per N of hose drag at Y = 0, L/2, L.
  double inertial_lag_um_per_m_s2[3] = {0, 0, 0};
  double drag_compliance_um_per_N[3] = {0, 0, 0};
};
ModalSummary modal_summary(const MachineParameters& p);

/// The move as this machine's controller runs it: the machine's dwell and smoothing replace the
/// move's (a jerk limit of the move stays and the tighter one wins, docs/dynamic-errors.md).
inline motion::ProbingMove controlled_move(const MachineParameters& p, motion::ProbingMove move) {
  move.dwell = p.controller_dwell_s;
  move.smoothing = p.controller_smoothing_s;
  return move;
}

/// A named machine: its parameters, what its controller lets a program set, and where they came
/// from.
struct Machine {
  std::string name;         ///< short identifier
  std::string description;  ///< free text (how it was obtained)
  MachineParameters parameters;
  /// The range of every setting of a probing cycle the controller accepts (the [capabilities]
  /// section; a format-2 file: any move within MoveLimits at the [controller] timing). The
  /// [controller] dwell and smoothing, the controller's own setting, lie inside them.
  motion::ControllerCapabilities capabilities = motion::fixed_timing_capabilities(
      MachineParameters{}.controller_dwell_s, MachineParameters{}.controller_smoothing_s);
};

/// Empty when `cycle` (a move with its dwell and smoothing) is one the machine's controller can
/// run; otherwise one sentence naming the first setting outside its capabilities, its value and
/// range in the file's units, and where the range is set.
std::string capability_problem(const Machine& machine, const motion::ProbingMove& cycle);
/// The same against `caps` for the machine named `machine_name`.
std::string capability_problem(const std::string& machine_name,
                               const motion::ControllerCapabilities& caps,
                               const motion::ProbingMove& cycle);

/// Empty when every capability range is ordered (min <= max) inside its setting's limits and
/// holds the [controller] dwell and smoothing; otherwise the first problem, naming the keys.
std::string capabilities_problem(const Machine& machine);

/// The table every machine-file operation iterates: section, key, unit, bounds.
const std::vector<ParameterInfo<MachineParameters>>& machine_parameter_table();

/// Version of the machine-file format this library writes. It reads this one, format 3 (no
/// structure.carriage_mass_share and no [mode2] section: the first mode's frequency does not
/// depend on Y, no second mode) and format 2 (neither, and no [capabilities] section:
/// fixed_timing_capabilities of its [controller] timing).
inline constexpr int kMachineFileVersion = 4;
inline constexpr int kOldestMachineFileVersion = 2;

/// The default machine, compiled in from data/machines/default.toml: identified against the
/// paper's Tables 1, 2 and 4 (docs/machine-model.md).
Machine default_machine();

/// Parses machine-file text; `source` names it in messages. Throws ConfigError
/// "source:line: key 'section.key': what is wrong" for a syntax error, a wrong or missing
/// format_version (a format-1 file gets a message naming the change and the command that writes
/// a new start file), an unknown key, a missing key, a non-numeric or non-physical value, a
/// capability range out of order or not holding the [controller] timing.
Machine parse_machine(const std::string& text, const std::string& source);
/// Reads and parses a file (ConfigError when it cannot be opened).
Machine load_machine(const std::string& path);
/// Writes the machine as TOML with every key documented in a comment.
std::string format_machine(const Machine& machine);

/// The rows of docs/machine-file.md's key tables, as `cmmcomp-sim machine --keys` prints them:
/// one markdown row per parameter (section, key, range, plausible range, fitted, meaning, basis),
/// then one per capability key (capabilities, key, range it may span, setting, meaning, where it
/// is set).
std::string format_machine_keys();

/// Checks every parameter against the table's bounds; false with the reason in `why`.
bool is_physical(const MachineParameters& p, std::string* why);

/// One line per parameter outside its plausible range (physical, but unlike a real moving-bridge
/// CMM), naming the key, the value, the range and its basis; empty when every value is
/// plausible. The tools print them as `warning:` lines when they load a machine file.
std::vector<std::string> implausible_parameters(const MachineParameters& p);

}  // namespace cmmcomp::dynamics
