// SPDX-License-Identifier: MIT
/// @file The physical parameters of a moving-bridge CMM's X axis, and its machine file.
///
/// The lumped model (docs/machine-model.md) has four parts, each with physical parameters:
///  - servo: the drive follows the commanded profile through a position/velocity loop with
///    acceleration feed-forward (finite bandwidth), disturbed by every force on the bridge;
///  - bridge yaw: the drive acts on one leg, so inertia and the loads pulling on the carriage
///    twist the bridge about Z through the yaw stiffness and damping of bearings and supports;
///  - carriage: the carriage and ram bend laterally (X) on the beam under their inertia and the
///    loads; the beam acts as a cantilever from the drive leg, so the compliance grows with Y³;
///  - three speed-dependent drag loads (cable carrier, hoses, bellows and bearing drag, lumped):
///    each a drag force (linear + cubic in speed) reaching the carriage through a
///    mass-spring-damper, so it builds up and rings with its own time constant. These are
///    phenomenological: identified from measurements, not drawn from a drawing.
/// Machine files are TOML (docs/machine-file.md); every key carries its unit in its name.
#pragma once

#include <cmmcomp/dynamics/parameter_table.hpp>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// All physical parameters, SI units. Values of a default-constructed struct are placeholders;
/// use default_machine() or load_machine().
struct MachineParameters {
  /// One speed-dependent drag load (see the file comment).
  struct DragLoad {
    double mass_kg = 1.0;                ///< moving mass [kg]
    double stiffness_N_per_m = 100.0;    ///< attachment stiffness [N/m]
    double damping_Ns_per_m = 10.0;      ///< attachment damping [N s/m]
    double drag_linear_Ns_per_m = 0.0;   ///< drag force, linear term [N s/m]
    double drag_cubic_Ns3_per_m3 = 0.0;  ///< drag force, cubic term [N s³/m³]
  };
  static constexpr int kDragLoads = 3;

  // servo
  double servo_bandwidth_hz = 30.0;           ///< closed-loop position bandwidth [Hz]
  double servo_damping_ratio = 0.7;           ///< closed-loop damping ratio [-]
  double servo_feedforward_gain = 1.0;        ///< acceleration feed-forward gain [-]
  double servo_moving_mass_kg = 400.0;        ///< mass the X drive accelerates [kg]
  double servo_bearing_drag_Ns_per_m = 20.0;  ///< viscous drag of the air bearings [N s/m]
  // bridge yaw
  double yaw_inertia_kgm2 = 50.0;      ///< bridge yaw inertia about the drive leg [kg m²]
  double yaw_static_moment_kgm = 5.0;  ///< bridge first moment of mass about the drive leg [kg m]
  double yaw_stiffness_Nm_per_rad = 1e7;  ///< yaw stiffness of bearings and supports [N m/rad]
  double yaw_damping_Nms_per_rad = 1e4;   ///< yaw damping [N m s/rad]
  double scale_offset_m = 0.001;          ///< lever from the scale to the carriage at Y = 0 [m]
  // carriage and ram on the beam
  double carriage_mass_kg = 25.0;              ///< carriage + ram [kg]
  double carriage_damping_Ns_per_m = 9000.0;   ///< lateral damping of the carriage [N s/m]
  double beam_base_compliance_m_per_N = 1e-7;  ///< lateral compliance at Y = 0 [m/N]
  double beam_bending_EI_Nm2 = 5e5;            ///< lateral bending stiffness EI of the beam [N m²]
  // drag loads
  DragLoad load[kDragLoads]{};
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
