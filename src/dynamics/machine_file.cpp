// SPDX-License-Identifier: MIT
/// @file The machine parameter table and the TOML machine file.
#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/error.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cstdint>
#include <fstream>
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
template <double P::*Member>
double& member(P& p) {
  return p.*Member;
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
  s.hose_frequency_hz = 1.0 / (2.0 * kPi * p.hose_time_constant_s);
  s.smoothing_periods = p.controller_smoothing_s * p.mode_frequency_hz;
  for (int i = 0; i < 3; ++i) {
    const double phi = mode_shape(p, 0.5 * i * p.beam_length_m);
    s.inertial_lag_um_per_m_s2[i] = 1e6 * phi * p.mode_participation / (omega * omega);
    s.drag_compliance_um_per_N[i] = 1e6 * phi * phi / p.mode_stiffness_N_per_m;
  }
  return s;
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

/// The machine-file subset of TOML (docs/machine-file.md, "Syntax"), checked before toml++
/// sees the text: Debian's toml++ 3.3.0 asserts or reaches `unreachable` on some malformed
/// inputs (upstream issue #295), so it only ever parses lines of these forms, in printable
/// ASCII (UTF-8 inside strings and comments): blank, `# comment`, `[section]`, `key = value`
/// with a decimal number, `true`/`false` or a one-line basic or literal string as the value,
/// each optionally followed by a comment.
class SubsetChecker {
 public:
  SubsetChecker(const std::string& text, const std::string& source)
      : text_(text), source_(source) {}

  void check() {
    while (pos_ < text_.size()) {
      line_start_ = pos_;
      check_line();
      ++line_;
    }
  }

 private:
  [[noreturn]] void fail(const std::string& what) const {
    throw ConfigError(fmt::format("{}:{}:{}: syntax error: {} (docs/machine-file.md, 'Syntax')",
                                  source_,
                                  line_,
                                  pos_ - line_start_ + 1,
                                  what));
  }
  char peek() const { return pos_ < text_.size() ? text_[pos_] : '\n'; }
  bool at_end_of_line() const { return peek() == '\n' || peek() == '\r'; }
  void skip_blanks() {
    while (peek() == ' ' || peek() == '\t') ++pos_;
  }
  static bool is_bare(char c) {
    return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' ||
           c == '-';
  }
  void expect_printable() const {
    const auto c = static_cast<unsigned char>(peek());
    if (c < 0x20 || c > 0x7e) {
      fail(c >= 0x80 ? fmt::format("byte 0x{:02X}: only strings and comments may hold "
                                   "characters beyond ASCII",
                                   c)
                     : fmt::format("control character 0x{:02X}", c));
    }
  }
  /// Steps over one character of a string or comment: printable ASCII, or one well-formed
  /// UTF-8 sequence (no overlong form, no surrogate, at most U+10FFFF).
  void text_character() {
    const auto c = static_cast<unsigned char>(peek());
    if (c < 0x80) {
      expect_printable();
      ++pos_;
      return;
    }
    const int extra = (c >= 0xC2 && c <= 0xDF)   ? 1
                      : (c >= 0xE0 && c <= 0xEF) ? 2
                      : (c >= 0xF0 && c <= 0xF4) ? 3
                                                 : -1;
    if (extra < 0) fail(fmt::format("byte 0x{:02X} does not start a UTF-8 character", c));
    std::uint32_t cp = c & (0x3Fu >> extra);
    for (int k = 1; k <= extra; ++k) {
      const std::size_t at = pos_ + static_cast<std::size_t>(k);
      const auto b = at < text_.size() ? static_cast<unsigned char>(text_[at]) : 0u;
      if ((b & 0xC0u) != 0x80u) fail("incomplete UTF-8 character");
      cp = (cp << 6) | (b & 0x3Fu);
    }
    const std::uint32_t least = extra == 1 ? 0x80u : extra == 2 ? 0x800u : 0x10000u;
    if (cp < least || cp > 0x10FFFFu || (cp >= 0xD800u && cp <= 0xDFFFu)) {
      fail(fmt::format("invalid UTF-8 character U+{:04X}", cp));
    }
    pos_ += static_cast<std::size_t>(extra) + 1;
  }
  void bare_key(const char* what) {
    if (!is_bare(peek())) {
      if (!at_end_of_line()) expect_printable();
      fail(fmt::format("expected {} (letters, digits, _ or -)", what));
    }
    while (is_bare(peek())) ++pos_;
  }
  /// The rest of the line: blanks, then nothing or a comment, then the line end.
  void end_of_line() {
    skip_blanks();
    if (peek() == '#') {
      ++pos_;
      while (!at_end_of_line()) {
        if (peek() == '\t') {
          ++pos_;
        } else {
          text_character();
        }
      }
    }
    if (peek() == '\r') {
      if (pos_ + 1 >= text_.size() || text_[pos_ + 1] != '\n') {
        fail("a carriage return must end a line (CRLF)");
      }
      ++pos_;
    } else if (!at_end_of_line()) {
      expect_printable();
      fail(fmt::format("unexpected '{}'", peek()));
    }
    if (pos_ < text_.size()) ++pos_;  // the '\n'
  }
  void string_value() {
    ++pos_;  // the opening quote
    while (peek() != '"') {
      if (at_end_of_line()) fail(key_ + "a string must end on its line with '\"'");
      if (peek() == '\\') {
        ++pos_;
        const char e = peek();
        if (e == 'u' || e == 'U') {
          const std::size_t n = e == 'u' ? 4 : 8;
          for (std::size_t k = 1; k <= n; ++k) {
            const char h = pos_ + k < text_.size() ? text_[pos_ + k] : '\n';
            if (!std::isxdigit(static_cast<unsigned char>(h))) {
              fail(key_ + fmt::format("\\{} needs {} hexadecimal digits", e, n));
            }
          }
          pos_ += n;
        } else if (e != '"' && e != '\\' && e != 'b' && e != 't' && e != 'n' && e != 'f' &&
                   e != 'r') {
          fail(key_ +
               "unknown escape (TOML's are \\\" \\\\ \\b \\t \\n \\f \\r \\uXXXX \\UXXXXXXXX)");
        }
        ++pos_;
      } else {
        text_character();
      }
    }
    ++pos_;  // the closing quote
  }
  /// 'literal': no escapes (what the writer uses when the text has no ' of its own).
  void literal_string_value() {
    ++pos_;
    while (peek() != '\'') {
      if (at_end_of_line()) fail(key_ + "a string must end on its line with \"'\"");
      text_character();
    }
    ++pos_;
  }
  static bool digits(const std::string& t, std::size_t& i) {
    const std::size_t begin = i;
    while (i < t.size() && ((t[i] >= '0' && t[i] <= '9') || (t[i] == '_' && i > begin))) ++i;
    return i > begin && t[i - 1] != '_';
  }
  /// true, false, or a decimal number: [+-] (inf | nan | D [. D] [(e|E) [+-] D]), D digits
  /// with single '_' between them. Dates, times and 0x/0o/0b integers are not in the subset.
  static bool is_scalar(const std::string& t) {
    if (t == "true" || t == "false") return true;
    std::size_t i = (!t.empty() && (t[0] == '+' || t[0] == '-')) ? 1 : 0;
    if (t.compare(i, std::string::npos, "inf") == 0 || t.compare(i, std::string::npos, "nan") == 0)
      return true;
    if (!digits(t, i)) return false;
    if (i < t.size() && t[i] == '.' && !digits(t, ++i)) return false;
    if (i < t.size() && (t[i] == 'e' || t[i] == 'E')) {
      ++i;
      if (i < t.size() && (t[i] == '+' || t[i] == '-')) ++i;
      if (!digits(t, i)) return false;
    }
    return i == t.size() && t.find("__") == std::string::npos;
  }
  void scalar_value() {
    const std::size_t begin = pos_;
    while (is_bare(peek()) || peek() == '+' || peek() == '.') ++pos_;
    const std::string token = text_.substr(begin, pos_ - begin);
    if (!is_scalar(token)) {
      pos_ = begin;
      if (token.empty()) expect_printable();
      fail(
          fmt::format("{}'{}' is not a value here: expected a decimal number, true, false or "
                      "a \"string\"",
                      key_,
                      token.empty() ? std::string(1, peek()) : token));
    }
  }
  void check_line() {
    skip_blanks();
    if (at_end_of_line() || peek() == '#') return end_of_line();
    if (peek() == '[') {
      ++pos_;
      skip_blanks();
      const std::size_t name = pos_;
      bare_key("a section name");
      section_ = text_.substr(name, pos_ - name) + ".";
      skip_blanks();
      if (peek() != ']') fail("expected ']' after the section name");
      ++pos_;
      return end_of_line();
    }
    const std::size_t key = pos_;
    bare_key("a key, a [section] or a # comment");
    key_ = "key '" + section_ + text_.substr(key, pos_ - key) + "': ";
    skip_blanks();
    if (peek() != '=') {
      if (!at_end_of_line()) expect_printable();
      fail(key_ + "expected '=' after the key");
    }
    ++pos_;
    skip_blanks();
    if (peek() == '"') {
      string_value();
    } else if (peek() == '\'') {
      literal_string_value();
    } else {
      scalar_value();
    }
    end_of_line();
    key_.clear();
  }

  const std::string& text_;
  const std::string& source_;
  std::size_t pos_ = 0;
  std::size_t line_start_ = 0;
  int line_ = 1;
  std::string section_;  // "servo." inside [servo]
  std::string key_;      // "key 'servo.bandwidth_hz': " while its value is checked
};

}  // namespace

Machine parse_machine(const std::string& text, const std::string& source) {
  SubsetChecker(text, source).check();
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
  if (version->is_integer() && version->as_integer()->get() == 1) {
    throw ConfigError(fmt::format(
        "{}: format_version 1 is the drag-load machine model; this library reads version {}, "
        "whose model has a structural mode, a hose element and controller settings "
        "(docs/machine-file.md, 'Format 2'). Write a new start file with "
        "'cmmcomp-sim machine -o start.toml' and identify it against your measurements",
        where(*version),
        kMachineFileVersion));
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
  const ModalSummary m = modal_summary(machine.parameters);
  fmt::format_to(std::back_inserter(s),
                 "\n# Derived (comments, not read back):\n"
                 "#   servo loop:      {:.3g} Hz, damping ratio {:.3g}\n"
                 "#   structural mode: {:.4g} Hz, damping ratio {:.3g}, modal mass {:.4g} kg\n"
                 "#   hose link:       {:.3g} Hz (1/(2 pi tau)), damping ratio 1 (critical)\n"
                 "#   smoothing:       {:.3g} periods of the structural mode\n"
                 "#   tip lag per m/s^2 at Y = 0, L/2, L: {:.4g}, {:.4g}, {:.4g} um\n"
                 "#   tip lag per N of hose drag at Y = 0, L/2, L: {:.4g}, {:.4g}, {:.4g} um\n",
                 m.servo_frequency_hz,
                 m.servo_damping_ratio,
                 m.mode_frequency_hz,
                 m.mode_damping_ratio,
                 m.mode_mass_kg,
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
