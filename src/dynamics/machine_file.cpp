// SPDX-License-Identifier: MIT
/// @file The machine parameter table and the TOML machine file.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cmmcomp/detail/did_you_mean.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/toml_subset.hpp>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>

namespace cmmcomp::dynamics {
namespace {

#include "default_machine_toml.inc"  // kDefaultMachineToml, generated from data/machines/

/// A one-line TOML basic string, in the machine-file subset (docs/machine-file.md, "Syntax"):
/// toml++'s own writer may choose a multi-line literal string, which the subset excludes.
std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (const char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\b':
        out += "\\b";
        break;
      case '\t':
        out += "\\t";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\f':
        out += "\\f";
        break;
      case '\r':
        out += "\\r";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
          out += fmt::format("\\u{:04X}", static_cast<unsigned char>(c));
        } else {
          out += c;
        }
    }
  }
  return out + "\"";
}

using P = MachineParameters;
using Info = ParameterInfo<P>;

/// Accessor that lets one table entry name a member.
template <double P::*kMember>
double& member(P& p) {
  return p.*kMember;
}

}  // namespace

// Each row: section, key, description, member, accepted range, fitted by default, plausible range
// and its basis. The plausible ranges bound identification; docs/machine-model.md explains them.
const std::vector<Info>& machine_parameter_table() {
  static const std::vector<Info> table = {
      {"servo",
       "bandwidth_hz",
       "closed-loop position bandwidth of the X drive",
       &member<&P::servo_bandwidth_hz>,
       1.0,
       500.0,
       false,
       10.0,
       100.0,
       "position loops of CMM drives: tens of Hz, below the first structural mode"},
      {"servo",
       "damping_ratio",
       "closed-loop damping ratio of the X drive",
       &member<&P::servo_damping_ratio>,
       0.05,
       5.0,
       false,
       0.5,
       1.0,
       "servo tuning practice (well damped, little overshoot)"},
      {"servo",
       "feedforward_gain",
       "acceleration feed-forward gain (1 = exact)",
       &member<&P::servo_feedforward_gain>,
       0.0,
       1.5,
       false,
       0.8,
       1.1,
       "a tuned feed-forward matches the moving mass to about 10 %"},
      {"servo",
       "moving_mass_kg",
       "mass the X drive accelerates (bridge, carriage, ram)",
       &member<&P::servo_moving_mass_kg>,
       1.0,
       1e5,
       false,
       100.0,
       2000.0,
       "moving bridges of 0.5-1 m CMMs (granite or aluminium)"},
      {"servo",
       "bearing_drag_Ns_per_m",
       "viscous drag of the air bearings on the drive",
       &member<&P::servo_bearing_drag_Ns_per_m>,
       0.0,
       1e6,
       false,
       0.0,
       10.0,
       "air-film shear: eta A / h = 1.8e-5 Pa s x 0.05 m^2 / 10 um = 0.1 N s/m per pad set"},
      {"structure",
       "mode_frequency_hz",
       "natural frequency of the dominant X mode of bridge and ram",
       &member<&P::mode_frequency_hz>,
       0.1,
       1000.0,
       true,
       10.0,
       50.0,
       "first bridge/ram modes of moving-bridge CMMs, and the paper's MPE ~ a/w^2 points to 19-27 "
       "Hz"},
      {"structure",
       "mode_damping_ratio",
       "modal damping ratio of that mode",
       &member<&P::mode_damping_ratio>,
       1e-4,
       2.0,
       false,
       0.02,
       0.1,
       "air films and bolted granite or aluminium joints dissipate little"},
      {"structure",
       "mode_stiffness_N_per_m",
       "modal stiffness at the tip for a force at the carriage (Y = 0)",
       &member<&P::mode_stiffness_N_per_m>,
       1e3,
       1e10,
       false,
       1e6,
       2e7,
       "k = m w^2 for a 100-200 kg modal mass at 10-50 Hz, a probe-tip stiffness of a few N/um"},
      {"structure",
       "participation",
       "inertial participation factor of the mode (tip-normalised at Y = 0)",
       &member<&P::mode_participation>,
       1e-3,
       10.0,
       true,
       0.1,
       1.6,
       "Gamma = sum(m phi) / sum(m phi^2): 1.57 for a uniform cantilever, less for a localised "
       "mode"},
      {"structure",
       "shape_growth",
       "phi(L) - 1: growth of the mode shape at the tip from Y = 0 to Y = L",
       &member<&P::mode_shape_growth>,
       0.0,
       20.0,
       true,
       0.0,
       3.0,
       "phi(Y) = 1 + g (Y/L)^3, the beam a cantilever from the drive leg, and Table 2 rises "
       "1.6-1.9x"},
      {"structure",
       "beam_length_m",
       "carriage travel L along the beam",
       &member<&P::beam_length_m>,
       0.01,
       10.0,
       false,
       0.2,
       3.0,
       "the paper's machine: Y = 0..500 mm"},
      {"structure",
       "carriage_mass_share",
       "mu: the carriage and ram's share of the mode's modal mass at Y = 0, f1(Y) = f1 / sqrt(1 + "
       "mu (phi(Y)^2 - 1))",
       &member<&P::mode_carriage_mass_share>,
       0.0,
       1.0,
       false,
       0.0,
       0.5,
       "carriage and ram are 5-40 % of the mode's modal mass (a light carriage on a granite "
       "bridge to a heavy ram on an aluminium one); moved out to where phi is 1.5-2x, they lower "
       "f1 by 2-25 % (Rayleigh quotient), 0 = f1 independent of Y",
       4,
       0.0},
      {"mode2",
       "frequency_hz",
       "natural frequency of the second X mode (ram bending, bridge torsion)",
       &member<&P::mode2_frequency_hz>,
       0.1,
       2000.0,
       false,
       25.0,
       200.0,
       "the next modes of moving-bridge CMMs lie at 2-5x the first",
       4,
       60.0},
      {"mode2",
       "damping_ratio",
       "modal damping ratio of the second mode",
       &member<&P::mode2_damping_ratio>,
       1e-4,
       2.0,
       false,
       0.01,
       0.1,
       "as the first mode: air films and bolted joints dissipate little",
       4,
       0.03},
      {"mode2",
       "participation",
       "inertial participation factor of the second mode (tip-normalised at Y = 0), 0 = no second "
       "mode",
       &member<&P::mode2_participation>,
       0.0,
       10.0,
       false,
       0.0,
       0.5,
       "a higher mode takes a smaller share of the drive's acceleration than the first (Gamma "
       "0.1-1.6)",
       4,
       0.0},
      {"mode2",
       "shape_growth",
       "psi(L) - 1: growth of the second mode's shape at the tip from Y = 0 to Y = L",
       &member<&P::mode2_shape_growth>,
       0.0,
       20.0,
       false,
       0.0,
       3.0,
       "psi(Y) = 1 + g2 (Y/L)^3, as the first mode's",
       4,
       0.0},
      {"hose",
       "time_constant_s",
       "time constant of the critically damped hose link",
       &member<&P::hose_time_constant_s>,
       1e-3,
       10.0,
       true,
       0.05,
       0.5,
       "hose and cable-carrier loops settle in 0.05-0.5 s after a speed change (overdamped)"},
      {"hose",
       "viscous_drag_Ns_per_m",
       "viscous drag of hoses and cable carrier at the carriage",
       &member<&P::hose_viscous_drag_Ns_per_m>,
       0.0,
       1e5,
       true,
       1.0,
       500.0,
       "a few N to 20 N over 10-100 mm/s: chain-link friction and hose bending losses"},
      {"hose",
       "coulomb_drag_N",
       "Coulomb (speed-independent) drag of hoses and cable carrier",
       &member<&P::hose_coulomb_drag_N>,
       0.0,
       1e4,
       true,
       0.5,
       30.0,
       "cable carriers and hoses: a few to about 20 N, mostly Coulomb"},
      {"hose",
       "coulomb_speed_m_per_s",
       "speed over which the Coulomb drag builds (tanh regularisation)",
       &member<&P::hose_coulomb_speed_m_per_s>,
       1e-6,
       1.0,
       false,
       1e-4,
       5e-3,
       "pre-sliding: the drag is established within a fraction of a mm/s"},
      {"hose",
       "accel_lag_s2",
       "delayed tip lag per unit of (link-filtered) acceleration, at Y = 0",
       &member<&P::hose_accel_lag_s2>,
       0.0,
       1e-2,
       true,
       0.0,
       2e-4,
       "phenomenological: what the paper's Table 4 needs (docs/machine-model.md)"},
      {"controller",
       "dwell_s",
       "settling dwell at rest at the pre-hit point before the approach",
       &member<&P::controller_dwell_s>,
       0.0,
       60.0,
       true,
       0.3,
       2.0,
       "controller setting: 0.5-1 s (>= 3 hose time constants) lets the structure settle"},
      {"controller",
       "smoothing_s",
       "command smoothing: moving average of the commanded acceleration",
       &member<&P::controller_smoothing_s>,
       0.0,
       1.0,
       false,
       0.0,
       0.1,
       "controller setting: one period of the dominant mode (20-100 ms) cancels its excitation"},
  };
  return table;
}

ModalSummary modal_summary(const MachineParameters& p) {
  constexpr double kPi = 3.14159265358979323846;
  ModalSummary s;
  s.servo_frequency_hz = p.servo_bandwidth_hz;
  s.servo_damping_ratio = p.servo_damping_ratio;
  s.mode_frequency_hz = p.mode_frequency_hz;
  s.mode_damping_ratio = p.mode_damping_ratio;
  const double omega = 2.0 * kPi * p.mode_frequency_hz;
  s.mode_mass_kg = p.mode_stiffness_N_per_m / (omega * omega);
  s.mode_frequency_at_end_hz = mode_frequency_at(p, p.beam_length_m);
  s.mode2_frequency_hz = has_second_mode(p) ? p.mode2_frequency_hz : 0.0;
  s.hose_frequency_hz = 1.0 / (2.0 * kPi * p.hose_time_constant_s);
  s.smoothing_periods = p.controller_smoothing_s * p.mode_frequency_hz;
  for (int i = 0; i < 3; ++i) {
    const double y = 0.5 * i * p.beam_length_m;
    const double phi = mode_shape(p, y);
    const double omega_y = 2.0 * kPi * mode_frequency_at(p, y);
    s.inertial_lag_um_per_m_s2[i] = 1e6 * phi * p.mode_participation / (omega_y * omega_y);
    if (has_second_mode(p)) {
      const double omega2 = 2.0 * kPi * p.mode2_frequency_hz;
      s.inertial_lag_um_per_m_s2[i] +=
          1e6 * mode2_shape(p, y) * p.mode2_participation / (omega2 * omega2);
    }
    s.drag_compliance_um_per_N[i] = 1e6 * phi * phi / p.mode_stiffness_N_per_m;
  }
  return s;
}

std::vector<std::string> implausible_parameters(const MachineParameters& p) {
  std::vector<std::string> out;
  for (const Info& info : machine_parameter_table()) {
    const double v = info.get(p);
    if (v >= info.plausible_min && v <= info.plausible_max) continue;
    out.push_back(fmt::format(
        "machine parameter '{}.{}' = {} is outside its plausible range [{:g}, {:g}] ({}): check "
        "the value and its unit",
        info.section,
        info.key,
        v,
        info.plausible_min,
        info.plausible_max,
        info.basis));
  }
  return out;
}

namespace {

using motion::kSettings;
using motion::SettingInfo;

std::string capability_key(const SettingInfo& info, const char* bound) {
  return fmt::format("{}_{}_{}", info.key, bound, info.unit);
}

/// "500 mm/s" from an SI value, in the file's unit.
std::string in_file_unit(const SettingInfo& info, double si) {
  return fmt::format("{:g} {}", si / info.to_si, info.unit_text);
}

/// The shortest text, in the file's unit, that reads back (times to_si, as the reader does) to
/// exactly `si`: a range fixed at a fitted dwell must still hold that dwell once read back.
std::string file_number(const SettingInfo& info, double si) {
  const double x = si / info.to_si;
  std::string best;
  for (const double candidate : {x, std::nextafter(x, HUGE_VAL), std::nextafter(x, -HUGE_VAL)}) {
    const std::string text = fmt::format("{}", candidate);
    if (std::strtod(text.c_str(), nullptr) * info.to_si != si) continue;
    if (best.empty() || text.size() < best.size()) best = text;
  }
  return best.empty() ? fmt::format("{}", x) : best;
}

std::string where_set(const SettingInfo& info) {
  return info.ipp_property != nullptr
             ? fmt::format("I++ DME {}", info.ipp_property)
             : std::string("the controller's configuration; I++ DME has no property for it");
}

}  // namespace

std::string capability_problem(const Machine& machine, const motion::ProbingMove& cycle) {
  return capability_problem(machine.name, machine.capabilities, cycle);
}

std::string capability_problem(const std::string& machine_name,
                               const motion::ControllerCapabilities& caps,
                               const motion::ProbingMove& cycle) {
  const motion::SettingViolation v = motion::first_violation(caps, cycle);
  if (!v.outside) return {};
  const SettingInfo& info = motion::setting_info(v.setting);
  return fmt::format(
      "the controller of machine '{}' cannot run {} = {}: its capabilities allow {:g} .. {} ({}; "
      "the machine file's [capabilities] {} and {}, docs/machine-file.md, 'Capabilities')",
      machine_name,
      info.symbol,
      std::isfinite(v.value) ? in_file_unit(info, v.value) : fmt::format("{}", v.value),
      v.range.min / info.to_si,
      in_file_unit(info, v.range.max),
      where_set(info),
      capability_key(info, "min"),
      capability_key(info, "max"));
}

std::string capabilities_problem(const Machine& machine) {
  for (const SettingInfo& info : kSettings) {
    const motion::SettingRange r = machine.capabilities[info.setting];
    if (!(info.limits.contains(r.min) && info.limits.contains(r.max) && r.min <= r.max)) {
      return fmt::format(
          "capabilities.{} = {:g} and capabilities.{} = {:g} must satisfy "
          "{:g} <= min <= max <= {:g} ({})",
          capability_key(info, "min"),
          r.min / info.to_si,
          capability_key(info, "max"),
          r.max / info.to_si,
          info.limits.min / info.to_si,
          info.limits.max / info.to_si,
          info.description);
    }
  }
  const struct {
    motion::Setting setting;
    double value;
    const char* key;
  } timing[] = {
      {motion::Setting::kDwell, machine.parameters.controller_dwell_s, "dwell_s"},
      {motion::Setting::kSmoothing, machine.parameters.controller_smoothing_s, "smoothing_s"}};
  for (const auto& t : timing) {
    const SettingInfo& info = motion::setting_info(t.setting);
    const motion::SettingRange r = machine.capabilities[t.setting];
    if (!r.contains(t.value)) {
      return fmt::format(
          "controller.{} = {} (the controller's own setting) is outside its capability "
          "{} .. {} (capabilities.{}, capabilities.{})",
          t.key,
          t.value,
          r.min,
          r.max,
          capability_key(info, "min"),
          capability_key(info, "max"));
    }
  }
  return {};
}

std::string format_machine_keys() {
  std::string out;
  for (const Info& info : machine_parameter_table()) {
    fmt::format_to(std::back_inserter(out),
                   "| {} | {} | {:g} .. {:g} | {:g} .. {:g} | {} | {} | {} |\n",
                   info.section,
                   info.key,
                   info.min,
                   info.max,
                   info.plausible_min,
                   info.plausible_max,
                   info.identifiable ? "yes" : "no",
                   info.description,
                   info.basis);
  }
  for (const SettingInfo& info : kSettings) {
    for (const char* bound : {"min", "max"}) {
      fmt::format_to(std::back_inserter(out),
                     "| capabilities | {} | {:g} .. {:g} | {} | {} {} | {} |\n",
                     capability_key(info, bound),
                     info.limits.min / info.to_si,
                     info.limits.max / info.to_si,
                     info.symbol,
                     bound == std::string("min") ? "smallest" : "largest",
                     info.description,
                     info.ipp_property != nullptr ? fmt::format("`{}`", info.ipp_property)
                                                  : std::string("configuration (no I++ property)"));
    }
  }
  return out;
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

namespace {

/// The [capabilities] keys into `caps` (SI), each recorded in `seen` as "capabilities.KEY".
template <typename Where>
void parse_capabilities(const toml::table& section,
                        const Where& where,
                        motion::ControllerCapabilities& caps,
                        std::set<std::string>& seen) {
  // Every key, its setting and bound, in kSettings order (min before max).
  std::vector<std::string> keys;
  for (const SettingInfo& info : kSettings) {
    keys.push_back(capability_key(info, "min"));
    keys.push_back(capability_key(info, "max"));
  }
  for (auto&& [sub, value] : section) {
    const std::string key(sub.str());
    const auto found = std::find(keys.begin(), keys.end(), key);
    if (found == keys.end()) {
      throw ConfigError(where(value) + ": unknown key 'capabilities." + key + "'" +
                        detail::did_you_mean(key, keys));
    }
    const auto index = static_cast<std::size_t>(found - keys.begin());
    const SettingInfo* info = &kSettings[index / 2];
    const bool is_min = index % 2 == 0;
    const std::optional<double> v = value.template value<double>();
    if (!v || !(value.is_floating_point() || value.is_integer()) || !std::isfinite(*v)) {
      throw ConfigError(where(value) + ": key 'capabilities." + key + "' must be a finite number");
    }
    motion::SettingRange& r = caps[info->setting];
    (is_min ? r.min : r.max) = *v * info->to_si;
    seen.insert("capabilities." + key);
  }
}

}  // namespace

Machine parse_machine(const std::string& text, const std::string& source) {
  io::check_toml_subset(text, source, "docs/machine-file.md");
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
    throw ConfigError(
        fmt::format("{}: missing 'format_version' (this library reads versions {} to {})",
                    source,
                    kOldestMachineFileVersion,
                    kMachineFileVersion));
  }
  if (version->is_integer() && version->as_integer()->get() == 1) {
    throw ConfigError(fmt::format(
        "{}: format_version 1 is the drag-load machine model; this library reads version {}, "
        "whose model has a structural mode, a hose element and controller settings "
        "(docs/machine-file.md, 'Format 2 and format 1'). Write a new start file with "
        "'cmmcomp-sim machine -o start.toml' and identify it against your measurements",
        where(*version),
        kMachineFileVersion));
  }
  if (!version->is_integer() || version->as_integer()->get() < kOldestMachineFileVersion ||
      version->as_integer()->get() > kMachineFileVersion) {
    throw ConfigError(
        fmt::format("{}: format_version must be {} to {} (this library's machine-file "
                    "formats)",
                    where(*version),
                    kOldestMachineFileVersion,
                    kMachineFileVersion));
  }
  const auto file_version = static_cast<int>(version->as_integer()->get());
  const bool has_capabilities = file_version >= 3;

  Machine m;
  std::set<std::string> seen;
  for (auto&& [key, node] : doc) {
    const std::string k(key.str());
    if (k == "format_version") continue;
    if (k == "name" || k == "description") {
      if (!node.is_string()) throw ConfigError(where(node) + ": '" + k + "' must be a string");
      const std::string& value = node.as_string()->get();
      // Escapes can still spell control characters: a name is printed in reports and
      // terminals, so none at all; a description may have tabs and line breaks.
      for (const char c : value) {
        const auto u = static_cast<unsigned char>(c);
        if ((u < 0x20 && !(k == "description" && (c == '\t' || c == '\n'))) || u == 0x7f) {
          throw ConfigError(
              fmt::format("{}: '{}' holds the control character 0x{:02X}", where(node), k, u));
        }
      }
      (k == "name" ? m.name : m.description) = value;
      continue;
    }
    const toml::table* section = node.as_table();
    if (section != nullptr && k == "capabilities") {
      if (!has_capabilities) {
        throw ConfigError(where(node) +
                          ": a [capabilities] section needs format_version 3 (format 2 has none; "
                          "docs/machine-file.md, 'Capabilities')");
      }
      parse_capabilities(*section, where, m.capabilities, seen);
      continue;
    }
    const bool known_section = std::any_of(machine_parameter_table().begin(),
                                           machine_parameter_table().end(),
                                           [&k](const Info& info) { return k == info.section; });
    if (section == nullptr) throw ConfigError(where(node) + ": unknown key '" + k + "'");
    if (!known_section) {
      // Name the first key when there is one (the likelier typo), else the section itself.
      if (!section->empty()) {
        const auto first = section->begin();
        std::vector<std::string> sections;
        for (const Info& info : machine_parameter_table()) sections.push_back(info.section);
        sections.emplace_back("capabilities");
        throw ConfigError(where(first->second) + ": unknown key '" + k + "." +
                          std::string(first->first.str()) + "' (no section '" + k + "')" +
                          detail::did_you_mean(k, sections));
      }
      std::vector<std::string> sections;
      for (const Info& info : machine_parameter_table()) sections.push_back(info.section);
      sections.emplace_back("capabilities");
      throw ConfigError(where(node) + ": unknown section '" + k + "'" +
                        detail::did_you_mean(k, sections));
    }
    for (auto&& [sub, value] : *section) {
      const std::string full = k + "." + std::string(sub.str());
      const Info* info = nullptr;
      for (const Info& candidate : machine_parameter_table()) {
        if (k == candidate.section && sub.str() == candidate.key) info = &candidate;
      }
      if (info == nullptr) {
        std::vector<std::string> keys;
        for (const Info& candidate : machine_parameter_table()) {
          if (k == candidate.section) keys.push_back(candidate.key);
        }
        throw ConfigError(where(value) + ": unknown key '" + full + "'" +
                          detail::did_you_mean(std::string(sub.str()), keys));
      }
      if (file_version < info->since_format) {
        throw ConfigError(fmt::format("{}: key '{}' needs format_version {} (docs/machine-file.md)",
                                      where(value),
                                      full,
                                      info->since_format));
      }
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
    if (seen.count(full) != 0) continue;
    if (file_version < info.since_format) {
      info.set(m.parameters, info.absent);  // an older format: the mechanism is absent
      continue;
    }
    throw ConfigError(source + ": missing key '" + full + "' (" + info.description + ")");
  }
  if (has_capabilities) {
    for (const SettingInfo& info : kSettings) {
      for (const char* bound : {"min", "max"}) {
        const std::string full = "capabilities." + capability_key(info, bound);
        if (seen.count(full) == 0) {
          throw ConfigError(fmt::format("{}: missing key '{}' (the {} {} the controller accepts)",
                                        source,
                                        full,
                                        bound == std::string("min") ? "smallest" : "largest",
                                        info.description));
        }
      }
    }
  } else {
    m.capabilities = motion::fixed_timing_capabilities(m.parameters.controller_dwell_s,
                                                       m.parameters.controller_smoothing_s);
  }
  const std::string problem = capabilities_problem(m);
  if (!problem.empty()) throw ConfigError(source + ": " + problem);
  if (m.name.empty()) throw ConfigError(source + ": missing 'name'");
  return m;
}

Machine load_machine(const std::string& path) {
  return parse_machine(io::read_file_bounded(path, "machine file", io::kMaxTextFileBytes), path);
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
    const double v = info.get(machine.parameters);
    fmt::format_to(std::back_inserter(s),
                   "{} = {}  # {}{}\n",
                   info.key,
                   v,
                   info.description,
                   v < info.plausible_min || v > info.plausible_max
                       ? fmt::format(" (OUTSIDE its plausible range {:g} .. {:g})",
                                     info.plausible_min,
                                     info.plausible_max)
                       : "");
  }
  fmt::format_to(std::back_inserter(s),
                 "\n[capabilities]  # what a program or the controller's configuration may set, "
                 "and the range the controller accepts\n");
  for (const SettingInfo& info : kSettings) {
    const motion::SettingRange r = machine.capabilities[info.setting];
    fmt::format_to(std::back_inserter(s),
                   "{} = {}\n{} = {}  # {}{} ({})\n",
                   capability_key(info, "min"),
                   file_number(info, r.min),
                   capability_key(info, "max"),
                   file_number(info, r.max),
                   info.description,
                   info.symbol == std::string(info.key) ? "" : std::string(" ") + info.symbol,
                   where_set(info));
  }
  const ModalSummary m = modal_summary(machine.parameters);
  fmt::format_to(std::back_inserter(s),
                 "\n# Derived (comments, not read back):\n"
                 "#   servo loop:      {:.3g} Hz, damping ratio {:.3g}\n"
                 "#   structural mode: {:.4g} Hz ({:.4g} Hz at Y = L), damping ratio {:.3g}, modal "
                 "mass {:.4g} kg\n"
                 "#   second mode:     {}\n"
                 "#   hose link:       {:.3g} Hz (1/(2 pi tau)), damping ratio 1 (critical)\n"
                 "#   smoothing:       {:.3g} periods of the structural mode\n"
                 "#   tip lag per m/s^2 at Y = 0, L/2, L: {:.4g}, {:.4g}, {:.4g} um\n"
                 "#   tip lag per N of hose drag at Y = 0, L/2, L: {:.4g}, {:.4g}, {:.4g} um\n",
                 m.servo_frequency_hz,
                 m.servo_damping_ratio,
                 m.mode_frequency_hz,
                 m.mode_frequency_at_end_hz,
                 m.mode_damping_ratio,
                 m.mode_mass_kg,
                 m.mode2_frequency_hz > 0.0 ? fmt::format("{:.4g} Hz, damping ratio {:.3g}",
                                                          m.mode2_frequency_hz,
                                                          machine.parameters.mode2_damping_ratio)
                                            : std::string("none"),
                 m.hose_frequency_hz,
                 m.smoothing_periods,
                 m.inertial_lag_um_per_m_s2[0],
                 m.inertial_lag_um_per_m_s2[1],
                 m.inertial_lag_um_per_m_s2[2],
                 m.drag_compliance_um_per_N[0],
                 m.drag_compliance_um_per_N[1],
                 m.drag_compliance_um_per_N[2]);
  return s;
}

Machine default_machine() { return parse_machine(kDefaultMachineToml, "<default machine>"); }

}  // namespace cmmcomp::dynamics
