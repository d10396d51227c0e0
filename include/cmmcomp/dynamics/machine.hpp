// SPDX-License-Identifier: MIT
/// @file The physical parameters of a moving-bridge CMM's X axis, and its machine file.
///
/// The lumped model (docs/machine-model.md) has five parts, each with physical parameters:
///  - servo: the drive follows the commanded profile through a position/velocity loop with
///    acceleration feed-forward (finite bandwidth), disturbed by every force on the bridge;
///  - bridge yaw: the drive acts on one leg, so inertia and the pull of attachments twist the
///    bridge about Z through the yaw stiffness and damping of the air bearings and supports;
///  - carriage: the carriage and ram on the beam bend laterally (X) under inertial load; the beam
///    acts as a cantilever from the drive leg, so its compliance grows with Y³;
///  - cable chain: the X energy chain at the idle leg, a soft mass-spring-damper with rolling drag
///    that grows with speed (linear + cubic), pulling on the bridge;
///  - hose: the air/cable hose of the carriage, another such appendage, pulling at the carriage.
/// Machine files are TOML (docs/machine-file.md); every key carries its unit in its name.
#pragma once

#include <cmmcomp/dynamics/parameter_table.hpp>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// All physical parameters, SI units. Values of a default-constructed struct are placeholders;
/// use default_machine() or load_machine().
struct MachineParameters {
  // servo
  double servo_bandwidth_hz = 25.0;           ///< closed-loop position bandwidth [Hz]
  double servo_damping_ratio = 0.9;           ///< closed-loop damping ratio [-]
  double servo_feedforward_gain = 1.0;        ///< acceleration feed-forward gain [-]
  double servo_moving_mass_kg = 400.0;        ///< bridge + carriage + ram mass the drive moves [kg]
  double servo_bearing_drag_Ns_per_m = 50.0;  ///< viscous drag of the air bearings [N s/m]
  // bridge yaw
  double yaw_inertia_kgm2 = 50.0;       ///< bridge yaw inertia about the drive leg [kg m²]
  double yaw_static_moment_kgm = 60.0;  ///< bridge first moment of mass about the drive leg [kg m]
  double yaw_stiffness_Nm_per_rad = 1.5e6;  ///< yaw stiffness of bearings and supports [N m/rad]
  double yaw_damping_Nms_per_rad = 900.0;   ///< yaw damping [N m s/rad]
  double idle_leg_arm_m = 1.0;              ///< distance drive leg → idle leg [m]
  double scale_offset_m = 0.05;             ///< distance drive leg/scale → carriage at Y = 0 [m]
  // carriage on the beam
  double carriage_mass_kg = 60.0;  ///< carriage + ram [kg]
  double carriage_damping_Ns_per_m =
      3000.0;  ///< lateral damping of the carriage on the beam [N s/m]
  double beam_base_compliance_m_per_N = 1e-8;  ///< lateral compliance at Y = 0 [m/N]
  double beam_bending_EI_Nm2 = 3e5;            ///< lateral bending stiffness EI of the beam [N m²]
  // cable chain (energy chain of the X axis, at the idle leg)
  double chain_mass_kg = 5.0;                 ///< moving mass of the chain [kg]
  double chain_stiffness_N_per_m = 580.0;     ///< attachment stiffness [N/m]
  double chain_damping_Ns_per_m = 25.0;       ///< attachment damping [N s/m]
  double chain_drag_linear_Ns_per_m = 300.0;  ///< rolling drag, linear term [N s/m]
  double chain_drag_cubic_Ns3_per_m3 = 1e3;   ///< rolling drag, cubic term [N s³/m³]
  // hose (carriage supply hose)
  double hose_mass_kg = 3.0;                ///< moving mass of the hose [kg]
  double hose_stiffness_N_per_m = 1250.0;   ///< attachment stiffness [N/m]
  double hose_damping_Ns_per_m = 27.0;      ///< attachment damping [N s/m]
  double hose_drag_linear_Ns_per_m = 1.0;   ///< drag, linear term [N s/m]
  double hose_drag_cubic_Ns3_per_m3 = 3e5;  ///< drag, cubic term [N s³/m³]
};

/// A named machine: its parameters and where they came from.
struct Machine {
  std::string name;         ///< short identifier
  std::string description;  ///< free text (how it was obtained)
  MachineParameters parameters;
};

/// The table every machine-file operation iterates: section, key, unit, bounds.
const std::vector<ParameterInfo<MachineParameters>>& machine_parameter_table();

/// Version of the machine-file format this library reads and writes.
inline constexpr int kMachineFileVersion = 1;

/// The default machine, compiled in from data/machines/default.toml: identified against the
/// paper's Tables 1, 2 and 4 (docs/machine-model.md).
Machine default_machine();

/// Parses machine-file text; `source` names it in messages. Throws ConfigError
/// "source:line: key 'section.key': what is wrong" for a syntax error, a wrong or missing
/// format_version, an unknown key, a missing key, a non-numeric or non-physical value.
Machine parse_machine(const std::string& text, const std::string& source);
/// Reads and parses a file (ConfigError when it cannot be opened).
Machine load_machine(const std::string& path);
/// Writes the machine as TOML with every key documented in a comment.
std::string format_machine(const Machine& machine);

/// Checks every parameter against the table's bounds; false with the reason in `why`.
bool is_physical(const MachineParameters& p, std::string* why);

}  // namespace cmmcomp::dynamics
