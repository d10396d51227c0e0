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

/// Accessors that let one table entry name a member, or a member of one drag load.
template <double P::*Member>
double& member(P& p) {
  return p.*Member;
}
template <int K, double P::DragLoad::*Member>
double& load_member(P& p) {
  return p.load[K].*Member;
}

template <int K>
void add_load(std::vector<Info>& t, const char* section) {
  using L = P::DragLoad;
  t.push_back({section,
               "mass_kg",
               "moving mass of the drag load",
               &load_member<K, &L::mass_kg>,
               1e-3,
               1e3,
               true});
  t.push_back({section,
               "stiffness_N_per_m",
               "stiffness through which the load pulls the carriage",
               &load_member<K, &L::stiffness_N_per_m>,
               1e-3,
               1e9,
               true});
  t.push_back({section,
               "damping_Ns_per_m",
               "damping through which the load pulls the carriage",
               &load_member<K, &L::damping_Ns_per_m>,
               1e-4,
               1e7,
               true});
  t.push_back({section,
               "drag_linear_Ns_per_m",
               "drag force, linear in speed",
               &load_member<K, &L::drag_linear_Ns_per_m>,
               0.0,
               1e7,
               true});
  t.push_back({section,
               "drag_cubic_Ns3_per_m3",
               "drag force, cubic in speed",
               &load_member<K, &L::drag_cubic_Ns3_per_m3>,
               0.0,
               1e10,
               true});
}

}  // namespace

const std::vector<Info>& machine_parameter_table() {
  static const std::vector<Info> table = [] {
    std::vector<Info> t = {
        {"servo",
         "bandwidth_hz",
         "closed-loop position bandwidth of the X drive",
         &member<&P::servo_bandwidth_hz>,
         1.0,
         500.0,
         false},
        {"servo",
         "damping_ratio",
         "closed-loop damping ratio of the X drive",
         &member<&P::servo_damping_ratio>,
         0.05,
         5.0,
         false},
        {"servo",
         "feedforward_gain",
         "acceleration feed-forward gain (1 = exact)",
         &member<&P::servo_feedforward_gain>,
         0.0,
         1.5,
         false},
        {"servo",
         "moving_mass_kg",
         "mass the X drive accelerates (bridge, carriage, ram)",
         &member<&P::servo_moving_mass_kg>,
         1.0,
         1e5,
         false},
        {"servo",
         "bearing_drag_Ns_per_m",
         "viscous drag of the air bearings on the drive",
         &member<&P::servo_bearing_drag_Ns_per_m>,
         0.0,
         1e6,
         false},
        {"bridge",
         "yaw_inertia_kgm2",
         "yaw inertia of the bridge about the drive leg",
         &member<&P::yaw_inertia_kgm2>,
         1e-3,
         1e5,
         false},
        {"bridge",
         "yaw_static_moment_kgm",
         "first moment of the bridge mass about the drive leg",
         &member<&P::yaw_static_moment_kgm>,
         0.0,
         1e5,
         false},
        {"bridge",
         "yaw_stiffness_Nm_per_rad",
         "yaw stiffness of air bearings and supports",
         &member<&P::yaw_stiffness_Nm_per_rad>,
         1.0,
         1e12,
         false},
        {"bridge",
         "yaw_damping_Nms_per_rad",
         "yaw damping of air bearings and supports",
         &member<&P::yaw_damping_Nms_per_rad>,
         0.0,
         1e9,
         false},
        {"bridge",
         "scale_offset_m",
         "lever from the drive leg (X scale) to the carriage at Y = 0",
         &member<&P::scale_offset_m>,
         0.0,
         5.0,
         true},
        {"carriage",
         "mass_kg",
         "mass of the carriage and ram",
         &member<&P::carriage_mass_kg>,
         1.0,
         1e4,
         false},
        {"carriage",
         "damping_Ns_per_m",
         "lateral (X) damping of the carriage on the beam",
         &member<&P::carriage_damping_Ns_per_m>,
         0.0,
         1e9,
         false},
        {"beam",
         "base_compliance_m_per_N",
         "lateral compliance at the carriage for Y = 0",
         &member<&P::beam_base_compliance_m_per_N>,
         1e-12,
         1e-3,
         true},
        {"beam",
         "bending_EI_Nm2",
         "lateral bending stiffness EI (cantilever from the drive leg)",
         &member<&P::beam_bending_EI_Nm2>,
         1.0,
         1e12,
         true},
    };
    add_load<0>(t, "load1");
    add_load<1>(t, "load2");
    add_load<2>(t, "load3");
    return t;
  }();
  return table;
}

bool is_physical(const MachineParameters& p, std::string* why) {
  for (const Info& info : machine_parameter_table()) {
    const double v = info.get(p);
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
        const auto first = section->begin();
        throw ConfigError(where(first->second) + ": unknown key '" + k + "." +
                          std::string(first->first.str()) + "' (no section '" + k + "')");
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
      info->set(m.parameters, *v);
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
                   info.get(machine.parameters),
                   info.description);
  }
  return s;
}

Machine default_machine() { return parse_machine(kDefaultMachineToml, "<default machine>"); }

}  // namespace cmmcomp::dynamics
