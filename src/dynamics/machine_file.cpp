// SPDX-License-Identifier: MIT
/// @file The machine parameter table and the TOML machine file.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/error.hpp>
#include <fstream>
#include <set>
#include <sstream>

namespace cmmcomp::dynamics {
namespace {

#include "default_machine_toml.inc"  // kDefaultMachineToml, generated from data/machines/

/// A TOML basic string, escaped by toml++ itself.
std::string quoted(const std::string& s) {
  std::ostringstream out;
  out << toml::value<std::string>(s);
  return out.str();
}

using P = MachineParameters;
using Info = ParameterInfo<P>;

}  // namespace

const std::vector<Info>& machine_parameter_table() {
  static const std::vector<Info> table = {
      {"servo",
       "bandwidth_hz",
       "closed-loop position bandwidth of the X drive",
       &P::servo_bandwidth_hz,
       1.0,
       500.0,
       false},
      {"servo",
       "damping_ratio",
       "closed-loop damping ratio of the X drive",
       &P::servo_damping_ratio,
       0.05,
       5.0,
       false},
      {"servo",
       "feedforward_gain",
       "acceleration feed-forward gain (1 = exact)",
       &P::servo_feedforward_gain,
       0.0,
       1.5,
       false},
      {"servo",
       "moving_mass_kg",
       "mass the X drive accelerates (bridge, carriage, ram)",
       &P::servo_moving_mass_kg,
       1.0,
       1e5,
       false},
      {"servo",
       "bearing_drag_Ns_per_m",
       "viscous drag of the air bearings on the drive",
       &P::servo_bearing_drag_Ns_per_m,
       0.0,
       1e6,
       false},
      {"bridge",
       "yaw_inertia_kgm2",
       "yaw inertia of the bridge about the drive leg",
       &P::yaw_inertia_kgm2,
       1e-3,
       1e5,
       true},
      {"bridge",
       "yaw_static_moment_kgm",
       "first moment of the bridge mass about the drive leg",
       &P::yaw_static_moment_kgm,
       0.0,
       1e5,
       true},
      {"bridge",
       "yaw_stiffness_Nm_per_rad",
       "yaw stiffness of air bearings and supports",
       &P::yaw_stiffness_Nm_per_rad,
       1.0,
       1e12,
       true},
      {"bridge",
       "yaw_damping_Nms_per_rad",
       "yaw damping of air bearings and supports",
       &P::yaw_damping_Nms_per_rad,
       0.0,
       1e9,
       true},
      {"bridge",
       "idle_leg_arm_m",
       "distance from the drive leg to the idle leg",
       &P::idle_leg_arm_m,
       0.01,
       20.0,
       false},
      {"bridge",
       "scale_offset_m",
       "distance from the drive leg (scale) to the carriage at Y = 0",
       &P::scale_offset_m,
       0.0,
       5.0,
       false},
      {"carriage", "mass_kg", "mass of the carriage and ram", &P::carriage_mass_kg, 0.1, 1e4, true},
      {"carriage",
       "damping_Ns_per_m",
       "lateral (X) damping of the carriage on the beam",
       &P::carriage_damping_Ns_per_m,
       0.0,
       1e9,
       true},
      {"beam",
       "base_compliance_m_per_N",
       "lateral compliance at the carriage for Y = 0",
       &P::beam_base_compliance_m_per_N,
       1e-12,
       1e-3,
       true},
      {"beam",
       "bending_EI_Nm2",
       "lateral bending stiffness EI (cantilever from the drive leg)",
       &P::beam_bending_EI_Nm2,
       1.0,
       1e12,
       true},
      {"cable_chain",
       "mass_kg",
       "moving mass of the X energy chain",
       &P::chain_mass_kg,
       1e-3,
       1e3,
       true},
      {"cable_chain",
       "stiffness_N_per_m",
       "stiffness of the chain's attachment to the bridge",
       &P::chain_stiffness_N_per_m,
       1e-3,
       1e9,
       true},
      {"cable_chain",
       "damping_Ns_per_m",
       "damping of the chain's attachment",
       &P::chain_damping_Ns_per_m,
       0.0,
       1e7,
       true},
      {"cable_chain",
       "drag_linear_Ns_per_m",
       "rolling drag of the chain, linear in speed",
       &P::chain_drag_linear_Ns_per_m,
       0.0,
       1e7,
       true},
      {"cable_chain",
       "drag_cubic_Ns3_per_m3",
       "rolling drag of the chain, cubic in speed",
       &P::chain_drag_cubic_Ns3_per_m3,
       0.0,
       1e10,
       true},
      {"hose",
       "mass_kg",
       "moving mass of the carriage supply hose",
       &P::hose_mass_kg,
       1e-3,
       1e3,
       true},
      {"hose",
       "stiffness_N_per_m",
       "stiffness of the hose's attachment to the carriage",
       &P::hose_stiffness_N_per_m,
       1e-3,
       1e9,
       true},
      {"hose",
       "damping_Ns_per_m",
       "damping of the hose's attachment",
       &P::hose_damping_Ns_per_m,
       0.0,
       1e7,
       true},
      {"hose",
       "drag_linear_Ns_per_m",
       "drag on the hose, linear in speed",
       &P::hose_drag_linear_Ns_per_m,
       0.0,
       1e7,
       true},
      {"hose",
       "drag_cubic_Ns3_per_m3",
       "drag on the hose, cubic in speed",
       &P::hose_drag_cubic_Ns3_per_m3,
       0.0,
       1e10,
       true},
  };
  return table;
}

bool is_physical(const MachineParameters& p, std::string* why) {
  for (const Info& info : machine_parameter_table()) {
    const double v = p.*info.field;
    if (!(v >= info.min && v <= info.max)) {
      if (why != nullptr) {
        *why = fmt::format("'{}.{}' = {} is outside its physical range [{:g}, {:g}]",
                           info.section,
                           info.key,
                           v,
                           info.min,
                           info.max);
      }
      return false;
    }
  }
  return true;
}

Machine parse_machine(const std::string& text, const std::string& source) {
  toml::table doc;
  try {
    doc = toml::parse(text, source);
  } catch (const toml::parse_error& e) {
    throw ConfigError(fmt::format(
        "{}:{}: TOML syntax error: {}", source, e.source().begin.line, e.description()));
  }
  auto where = [&source](const toml::node& n) {
    return fmt::format("{}:{}", source, n.source().begin.line);
  };

  const toml::node* version = doc.get("format_version");
  if (version == nullptr) {
    throw ConfigError(source + ": missing 'format_version' (this library reads version " +
                      std::to_string(kMachineFileVersion) + ")");
  }
  if (!version->is_integer() || version->as_integer()->get() != kMachineFileVersion) {
    throw ConfigError(
        fmt::format("{}: format_version must be {} (this library's machine-file "
                    "format)",
                    where(*version),
                    kMachineFileVersion));
  }

  Machine m;
  std::set<std::string> seen;
  for (auto&& [key, node] : doc) {
    const std::string k(key.str());
    if (k == "format_version") continue;
    if (k == "name" || k == "description") {
      if (!node.is_string()) throw ConfigError(where(node) + ": '" + k + "' must be a string");
      (k == "name" ? m.name : m.description) = node.as_string()->get();
      continue;
    }
    const toml::table* section = node.as_table();
    const bool known_section = std::any_of(machine_parameter_table().begin(),
                                           machine_parameter_table().end(),
                                           [&k](const Info& info) { return k == info.section; });
    if (section == nullptr) throw ConfigError(where(node) + ": unknown key '" + k + "'");
    if (!known_section) {
      // Name the first key when there is one (the likelier typo), else the section itself.
      if (!section->empty()) {
        const auto& [first_key, first_value] = *section->begin();
        throw ConfigError(where(first_value) + ": unknown key '" + k + "." +
                          std::string(first_key.str()) + "' (no section '" + k + "')");
      }
      throw ConfigError(where(node) + ": unknown section '" + k + "'");
    }
    for (auto&& [sub, value] : *section) {
      const std::string full = k + "." + std::string(sub.str());
      const Info* info = nullptr;
      for (const Info& candidate : machine_parameter_table()) {
        if (k == candidate.section && sub.str() == candidate.key) info = &candidate;
      }
      if (info == nullptr) throw ConfigError(where(value) + ": unknown key '" + full + "'");
      const std::optional<double> v = value.value<double>();
      if (!v || !(value.is_floating_point() || value.is_integer())) {
        throw ConfigError(where(value) + ": key '" + full + "' must be a number");
      }
      if (!(*v >= info->min && *v <= info->max)) {
        throw ConfigError(fmt::format("{}: key '{}' = {} is not physical (allowed {:g} .. {:g})",
                                      where(value),
                                      full,
                                      *v,
                                      info->min,
                                      info->max));
      }
      m.parameters.*info->field = *v;
      seen.insert(full);
    }
  }
  for (const Info& info : machine_parameter_table()) {
    const std::string full = std::string(info.section) + "." + info.key;
    if (seen.count(full) == 0) {
      throw ConfigError(source + ": missing key '" + full + "' (" + info.description + ")");
    }
  }
  if (m.name.empty()) throw ConfigError(source + ": missing 'name'");
  return m;
}

Machine load_machine(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ConfigError(path + ": cannot open machine file");
  std::ostringstream text;
  text << in.rdbuf();
  return parse_machine(text.str(), path);
}

std::string format_machine(const Machine& machine) {
  std::string s;
  fmt::format_to(std::back_inserter(s),
                 "# cmmcomp machine file (docs/machine-file.md). Units are in the key names.\n"
                 "format_version = {}\nname = {}\ndescription = {}\n",
                 kMachineFileVersion,
                 quoted(machine.name),
                 quoted(machine.description));
  const char* section = "";
  for (const Info& info : machine_parameter_table()) {
    if (std::string(section) != info.section) {
      section = info.section;
      fmt::format_to(std::back_inserter(s), "\n[{}]\n", section);
    }
    // "{}" writes the shortest text that reads back to the same double: fitted values
    // round-trip exactly.
    fmt::format_to(std::back_inserter(s),
                   "{} = {}  # {}\n",
                   info.key,
                   machine.parameters.*info.field,
                   info.description);
  }
  return s;
}

Machine default_machine() { return parse_machine(kDefaultMachineToml, "<default machine>"); }

}  // namespace cmmcomp::dynamics
