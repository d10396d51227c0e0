// SPDX-License-Identifier: MIT
/// @file The versioned JSON model file: content checks, writing, the checksum rule, reading.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/io/sha256.hpp>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <set>
#include <sstream>

#include "model_file_internal.hpp"

namespace cmmcomp::io {
namespace {

using detail::centre_index;
using detail::consequent_index;
using detail::param_count;
using detail::rules_of;
using detail::width_index;
using Json = nlohmann::json;                 // keys sorted: the canonical form for the checksum
using OrderedJson = nlohmann::ordered_json;  // keys in writing order: the file a human reads

// ---------------------------------------------------------------------------------------------
// Shared checks and helpers.

std::string idx(int i) { return "[" + std::to_string(i) + "]"; }

bool is_lower_hex(const std::string& s, std::size_t n) {
  return s.size() == n && std::all_of(s.begin(), s.end(), [](char c) {
           return (c >= '0' && c <= '9') || (c >= 'a' && c <= 'f');
         });
}

bool is_digits(const std::string& s, std::size_t from, std::size_t n) {
  if (from + n > s.size()) return false;
  for (std::size_t i = from; i < from + n; ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
  }
  return true;
}

/// YYYY-MM-DDTHH:MM:SS[.f+]Z with plausible field ranges.
bool is_iso8601_utc(const std::string& s) {
  if (s.size() < 20 || !is_digits(s, 0, 4) || s[4] != '-' || !is_digits(s, 5, 2) || s[7] != '-' ||
      !is_digits(s, 8, 2) || s[10] != 'T' || !is_digits(s, 11, 2) || s[13] != ':' ||
      !is_digits(s, 14, 2) || s[16] != ':' || !is_digits(s, 17, 2) || s.back() != 'Z') {
    return false;
  }
  if (s.size() > 20 && (s[19] != '.' || s.size() < 22 || !is_digits(s, 20, s.size() - 21))) {
    return false;
  }
  const int month = std::stoi(s.substr(5, 2));
  const int day = std::stoi(s.substr(8, 2));
  return month >= 1 && month <= 12 && day >= 1 && day <= 31 && std::stoi(s.substr(11, 2)) < 24 &&
         std::stoi(s.substr(14, 2)) < 60 && std::stoi(s.substr(17, 2)) <= 60;
}

bool has_control_char(const std::string& s) {
  return std::any_of(
      s.begin(), s.end(), [](char c) { return static_cast<unsigned char>(c) < 0x20 || c == 0x7f; });
}

/// Everything about the content that is not structure: names, ranges, parameter values,
/// metadata. `where` prefixes every message ("model.json" or "model to write").
/// Checks `conditions` (the file's `conditions` object) for a model of `outputs` outputs;
/// `fail` throws.
template <typename Fail>
void check_conditions(const TrainingConditions& c, int outputs, const Fail& fail) {
  const auto range = [&](const std::optional<ConditionRange>& r, const char* name) {
    if (!r) return;
    if (!std::isfinite(r->lo) || !std::isfinite(r->hi) || !(r->lo > 0) || !(r->lo <= r->hi)) {
      fail(fmt::format(
          "conditions.{} = [{}, {}] must be finite with 0 < lo <= hi", name, r->lo, r->hi));
    }
  };
  range(c.pa_mm_s2, "pa_mm_s2");
  range(c.aa_mm_s2, "aa_mm_s2");
  const auto time = [&](const std::optional<double>& v, const char* name) {
    if (v && !(std::isfinite(*v) && *v >= 0)) {
      fail(fmt::format("conditions.{} = {} must be finite and >= 0", name, *v));
    }
  };
  time(c.dwell_s, "dwell_s");
  time(c.smoothing_s, "smoothing_s");
  if (has_control_char(c.axis)) fail("conditions.axis contains a control character");
  if (has_control_char(c.machine)) fail("conditions.machine contains a control character");
  if (!c.noise_floor.empty()) {
    if (c.noise_floor.size() != static_cast<std::size_t>(outputs)) {
      fail(fmt::format("conditions.noise_floor has {} values, expected one per output ({})",
                       c.noise_floor.size(),
                       outputs));
    }
    for (std::size_t o = 0; o < c.noise_floor.size(); ++o) {
      if (!std::isfinite(c.noise_floor[o]) || c.noise_floor[o] < 0) {
        fail(fmt::format(
            "conditions.noise_floor[{}] = {} must be finite and >= 0", o, c.noise_floor[o]));
      }
    }
  }
}

void check_content(const detail::ModelData& d, const std::string& where) {
  const auto fail = [&where](const std::string& what) { throw ConfigError(where + ": " + what); };
  const auto check_names = [&](const std::vector<std::string>& names,
                               const std::vector<std::string>& units,
                               const char* list) {
    std::set<std::string> seen;
    for (std::size_t i = 0; i < names.size(); ++i) {
      const std::string at = std::string(list) + idx(static_cast<int>(i));
      if (names[i].empty()) fail(at + ".name is empty");
      if (has_control_char(names[i])) fail(at + ".name contains a control character");
      if (has_control_char(units[i])) fail(at + ".unit contains a control character");
      if (!seen.insert(names[i]).second) fail(at + ".name '" + names[i] + "' is a duplicate");
    }
  };
  check_names(d.input_names, d.input_units, "inputs");
  check_names(d.output_names, d.output_units, "outputs");
  for (int i = 0; i < d.inputs; ++i) {
    const fuzzy::InputRange& r = d.ranges[static_cast<std::size_t>(i)];
    const std::string at = "inputs" + idx(i);
    if (!std::isfinite(r.lo)) fail(fmt::format("{}.lo = {} is not finite", at, r.lo));
    if (!std::isfinite(r.hi)) fail(fmt::format("{}.hi = {} is not finite", at, r.hi));
    if (!(r.lo < r.hi)) fail(fmt::format("{}: lo = {} must be < hi = {}", at, r.lo, r.hi));
    if (!std::isfinite(r.hi - r.lo)) fail(at + ": hi - lo overflows");
  }
  for (int i = 0; i < d.inputs; ++i) {
    for (int s = 0; s < d.sets; ++s) {
      const double c = d.params[centre_index(d, i, s)];
      if (!std::isfinite(c)) {
        fail(fmt::format("parameters.centres{}{} = {} is not finite", idx(i), idx(s), c));
      }
      const double w = d.params[width_index(d, i, s)];
      if (!std::isfinite(w)) {
        fail(fmt::format("parameters.widths{}{} = {} is not finite", idx(i), idx(s), w));
      }
      if (!(w > 0)) fail(fmt::format("parameters.widths{}{} = {} must be > 0", idx(i), idx(s), w));
    }
  }
  const int rules = rules_of(d.inputs, d.sets);
  for (int o = 0; o < d.outputs; ++o) {
    for (int j = 0; j < rules; ++j) {
      for (int k = 0; k <= d.inputs; ++k) {
        const double p = d.params[consequent_index(d, o, j, k)];
        if (!std::isfinite(p)) {
          fail(fmt::format(
              "parameters.consequents{}{}{} = {} is not finite", idx(o), idx(j), idx(k), p));
        }
      }
    }
  }
  const ModelMetadata& t = d.training;
  if (!t.data_file_sha256.empty() && !is_lower_hex(t.data_file_sha256, 64)) {
    fail("training.data_file_sha256 = '" + t.data_file_sha256 +
         "' must be 64 lower-case hex digits (SHA-256) or empty");
  }
  if (t.method.empty()) fail("training.method is empty");
  if (!std::isfinite(t.lambda) || t.lambda < 0) {
    fail(fmt::format("training.lambda = {} must be finite and >= 0", t.lambda));
  }
  if (t.cv_rmse.size() != static_cast<std::size_t>(d.outputs)) {
    fail(fmt::format("training.cv_rmse has {} values, expected one per output ({})",
                     t.cv_rmse.size(),
                     d.outputs));
  }
  for (std::size_t o = 0; o < t.cv_rmse.size(); ++o) {
    if (!std::isfinite(t.cv_rmse[o]) || t.cv_rmse[o] < 0) {
      fail(fmt::format("training.cv_rmse[{}] = {} must be finite and >= 0", o, t.cv_rmse[o]));
    }
  }
  if (!is_iso8601_utc(t.trained_at)) {
    fail("training.trained_at = '" + t.trained_at +
         "' is not ISO-8601 UTC (YYYY-MM-DDTHH:MM:SSZ, optional fraction of a second)");
  }
  if (t.tool_version.empty()) fail("training.tool_version is empty");
  check_conditions(d.conditions, d.outputs, fail);
  if (d.interval_coverage == 0) {
    if (!d.interval_half_width.empty() || !d.interval_gain.empty() ||
        !d.interval_corner_gain.empty()) {
      fail("uncertainty values without a coverage");
    }
    return;
  }
  if (!(d.interval_coverage > 0 && d.interval_coverage < 1)) {
    fail(fmt::format("uncertainty.coverage = {} must be in (0, 1)", d.interval_coverage));
  }
  if (d.interval_half_width.size() != static_cast<std::size_t>(d.outputs) ||
      d.interval_gain.size() != static_cast<std::size_t>(d.outputs) ||
      d.interval_corner_gain.size() != static_cast<std::size_t>(d.outputs)) {
    fail(fmt::format(
        "uncertainty: expected one half_width, extrapolation_gain and corner_gain per output ({})",
        d.outputs));
  }
  for (std::size_t o = 0; o < d.interval_half_width.size(); ++o) {
    const double h = d.interval_half_width[o];
    const double g = d.interval_gain[o];
    if (!std::isfinite(h) || h < 0) {
      fail(fmt::format("uncertainty.half_width[{}] = {} must be finite and >= 0", o, h));
    }
    if (!std::isfinite(g) || g < 0) {
      fail(fmt::format("uncertainty.extrapolation_gain[{}] = {} must be finite and >= 0", o, g));
    }
    const double k = d.interval_corner_gain[o];
    if (!std::isfinite(k) || k < 0) {
      fail(fmt::format("uncertainty.corner_gain[{}] = {} must be finite and >= 0", o, k));
    }
  }
  if (d.interval_method.empty()) fail("uncertainty.method is empty");
  if (has_control_char(d.interval_method)) fail("uncertainty.method contains a control character");
  if (d.interval_samples == 0) fail("uncertainty.calibration_samples must be > 0");
}

void check_sizes(const detail::ModelData& d) {
  const auto in = static_cast<std::size_t>(d.inputs);
  const auto out = static_cast<std::size_t>(d.outputs);
  if (d.input_names.size() != in || d.input_units.size() != in || d.ranges.size() != in ||
      d.output_names.size() != out || d.output_units.size() != out ||
      d.params.size() != static_cast<std::size_t>(param_count(d.inputs, d.sets, d.outputs))) {
    throw ConfigError("model to write: inconsistent sizes");  // only via detail:: misuse
  }
}

/// The document without `checksum`, as J (Json: sorted keys; OrderedJson: writing order).
template <typename J>
J to_json(const detail::ModelData& d) {
  J doc;
  doc["format"] = kModelFileFormat;
  doc["format_version"] = kModelFileVersion;
  J arch;
  arch["inputs"] = d.inputs;
  arch["sets_per_input"] = d.sets;
  arch["outputs"] = d.outputs;
  arch["rules"] = rules_of(d.inputs, d.sets);
  arch["parameter_count"] = param_count(d.inputs, d.sets, d.outputs);
  arch["membership"] = "gaussian";
  arch["consequent"] = "first-order";
  doc["architecture"] = std::move(arch);
  J inputs = J::array();
  for (int i = 0; i < d.inputs; ++i) {
    const auto u = static_cast<std::size_t>(i);
    J in;
    in["name"] = d.input_names[u];
    in["unit"] = d.input_units[u];
    in["lo"] = d.ranges[u].lo;
    in["hi"] = d.ranges[u].hi;
    inputs.push_back(std::move(in));
  }
  doc["inputs"] = std::move(inputs);
  J outputs = J::array();
  for (int o = 0; o < d.outputs; ++o) {
    const auto u = static_cast<std::size_t>(o);
    J out;
    out["name"] = d.output_names[u];
    out["unit"] = d.output_units[u];
    outputs.push_back(std::move(out));
  }
  doc["outputs"] = std::move(outputs);
  J centres = J::array();
  J widths = J::array();
  for (int i = 0; i < d.inputs; ++i) {
    J c = J::array();
    J w = J::array();
    for (int s = 0; s < d.sets; ++s) {
      c.push_back(d.params[centre_index(d, i, s)]);
      w.push_back(d.params[width_index(d, i, s)]);
    }
    centres.push_back(std::move(c));
    widths.push_back(std::move(w));
  }
  J consequents = J::array();
  for (int o = 0; o < d.outputs; ++o) {
    J block = J::array();
    for (int j = 0; j < rules_of(d.inputs, d.sets); ++j) {
      J rule = J::array();
      for (int k = 0; k <= d.inputs; ++k) rule.push_back(d.params[consequent_index(d, o, j, k)]);
      block.push_back(std::move(rule));
    }
    consequents.push_back(std::move(block));
  }
  J params;
  params["centres"] = std::move(centres);
  params["widths"] = std::move(widths);
  params["consequents"] = std::move(consequents);
  doc["parameters"] = std::move(params);
  J training;
  training["data_file_sha256"] = d.training.data_file_sha256;
  training["method"] = d.training.method;
  training["lambda"] = d.training.lambda;
  training["cv_rmse"] = d.training.cv_rmse;
  training["trained_at"] = d.training.trained_at;
  training["seed"] = d.training.seed;
  training["tool_version"] = d.training.tool_version;
  doc["training"] = std::move(training);
  const TrainingConditions& c = d.conditions;
  J conditions;
  const auto range = [](const std::optional<ConditionRange>& r) {
    if (!r) return J(nullptr);
    J j;
    j["lo"] = r->lo;
    j["hi"] = r->hi;
    return j;
  };
  const auto optional_number = [](const std::optional<double>& v) {
    return v ? J(*v) : J(nullptr);
  };
  const auto optional_text = [](const std::string& v) { return v.empty() ? J(nullptr) : J(v); };
  conditions["pa_mm_s2"] = range(c.pa_mm_s2);
  conditions["aa_mm_s2"] = range(c.aa_mm_s2);
  conditions["dwell_s"] = optional_number(c.dwell_s);
  conditions["smoothing_s"] = optional_number(c.smoothing_s);
  conditions["axis"] = optional_text(c.axis);
  conditions["machine"] = optional_text(c.machine);
  conditions["noise_floor"] = c.noise_floor.empty() ? J(nullptr) : J(c.noise_floor);
  doc["conditions"] = std::move(conditions);
  if (d.interval_coverage > 0) {
    J u;
    u["coverage"] = d.interval_coverage;
    u["half_width"] = d.interval_half_width;
    u["extrapolation_gain"] = d.interval_gain;
    u["corner_gain"] = d.interval_corner_gain;
    u["method"] = d.interval_method;
    u["calibration_samples"] = d.interval_samples;
    doc["uncertainty"] = std::move(u);
  } else {
    doc["uncertainty"] = nullptr;
  }
  return doc;
}

/// The checksum rule: SHA-256 of the compact dump of the key-sorted document without
/// `checksum` (nlohmann's dump: no whitespace, shortest round-trip numbers, UTF-8 strings).
std::string checksum_of(const Json& doc_without_checksum) {
  return sha256_hex(doc_without_checksum.dump());
}

bool is_primitive(const OrderedJson& j) { return !j.is_object() && !j.is_array(); }

/// Pretty printer: 2-space indent; arrays of numbers and objects of scalars on one line.
void write_pretty(const OrderedJson& j, int indent, std::string& out) {
  const std::string pad(static_cast<std::size_t>(indent), ' ');
  const std::string inner(static_cast<std::size_t>(indent + 2), ' ');
  if (j.is_object() && !j.empty()) {
    const bool flat = indent > 0 && std::all_of(j.begin(), j.end(), is_primitive);
    out += flat ? "{" : "{\n";
    bool first = true;
    for (auto it = j.begin(); it != j.end(); ++it) {
      if (!first) out += flat ? ", " : ",\n";
      first = false;
      if (!flat) out += inner;
      out += Json(it.key()).dump() + ": ";
      write_pretty(it.value(), indent + 2, out);
    }
    out += flat ? "}" : "\n" + pad + "}";
  } else if (j.is_array() && !j.empty()) {
    const bool flat = std::all_of(j.begin(), j.end(), is_primitive);
    out += flat ? "[" : "[\n";
    bool first = true;
    for (const OrderedJson& e : j) {
      if (!first) out += flat ? ", " : ",\n";
      first = false;
      if (!flat) out += inner;
      write_pretty(e, indent + 2, out);
    }
    out += flat ? "]" : "\n" + pad + "]";
  } else {
    out += j.dump();
  }
}

// ---------------------------------------------------------------------------------------------
// Reading.

/// Typed access to a parsed document with messages "source: path ...".
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void fail(const std::string& what) const {
    throw ConfigError(source_ + ": " + what);
  }

  const Json& key(const Json& obj, const std::string& path, const char* name) const {
    const auto it = obj.find(name);
    if (it == obj.end()) fail("missing key '" + join(path, name) + "'");
    return *it;
  }
  void only_keys(const Json& obj,
                 const std::string& path,
                 std::initializer_list<const char*> allowed) const {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      const bool known = std::any_of(
          allowed.begin(), allowed.end(), [&it](const char* a) { return it.key() == a; });
      if (!known) fail("unknown key '" + join(path, it.key().c_str()) + "'");
    }
  }
  const Json& object(const Json& obj, const std::string& path, const char* name) const {
    const Json& v = key(obj, path, name);
    if (!v.is_object()) fail(join(path, name) + " must be an object, got " + describe(v));
    return v;
  }
  const Json& array(const Json& obj,
                    const std::string& path,
                    const char* name,
                    std::size_t size) const {
    return sized(key(obj, path, name), join(path, name), size);
  }
  const Json& sized(const Json& v, const std::string& at, std::size_t size) const {
    if (!v.is_array()) fail(at + " must be an array, got " + describe(v));
    if (v.size() != size) {
      fail(fmt::format("{} has {} elements, expected {}", at, v.size(), size));
    }
    return v;
  }
  std::string string(const Json& obj, const std::string& path, const char* name) const {
    const Json& v = key(obj, path, name);
    if (!v.is_string()) fail(join(path, name) + " must be a string, got " + describe(v));
    return v.get<std::string>();
  }
  long long integer(const Json& obj, const std::string& path, const char* name) const {
    const Json& v = key(obj, path, name);
    if (!v.is_number_integer()) fail(join(path, name) + " must be an integer, got " + describe(v));
    if (v.is_number_unsigned() && v.get<std::uint64_t>() > (1ULL << 62)) {
      fail(join(path, name) + " is too large");
    }
    return v.get<long long>();
  }
  std::uint64_t unsigned_integer(const Json& obj, const std::string& path, const char* name) const {
    const Json& v = key(obj, path, name);
    if (!v.is_number_unsigned()) {
      fail(join(path, name) + " must be an integer >= 0, got " + describe(v));
    }
    return v.get<std::uint64_t>();
  }
  double number(const Json& v, const std::string& at) const {
    if (!v.is_number()) fail(at + " must be a number, got " + describe(v));
    const double x = v.get<double>();
    if (!std::isfinite(x)) fail(at + " = " + v.dump() + " is not finite");
    return x;
  }
  double number(const Json& obj, const std::string& path, const char* name) const {
    return number(key(obj, path, name), join(path, name));
  }

  static std::string join(const std::string& path, const char* name) {
    return path.empty() ? std::string(name) : path + "." + name;
  }
  static std::string describe(const Json& v) {
    if (v.is_null()) return "null";
    std::string text = v.dump();
    if (text.size() > 40) text = text.substr(0, 37) + "...";
    return std::string(v.type_name()) + " " + text;
  }

 private:
  std::string source_;
};

// Nesting deeper than any model file needs: refused before the parser and the recursive
// dump/destroy of nlohmann::json can overflow the stack on a hostile file.
constexpr int kMaxJsonDepth = 32;

// The deepest nesting of arrays and objects in `text` (outside strings), scanning once.
int json_depth(const std::string& text) {
  int depth = 0;
  int deepest = 0;
  bool in_string = false;
  bool escaped = false;
  for (const char c : text) {
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      deepest = std::max(deepest, ++depth);
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return deepest;
}

Json parse_document(const std::string& text, const std::string& source) {
  if (text.size() > kMaxModelFileBytes) {
    throw ConfigError(fmt::format("{}: {} bytes, more than the {} bytes a model file may have",
                                  source,
                                  text.size(),
                                  kMaxModelFileBytes));
  }
  if (json_depth(text) > kMaxJsonDepth) {
    throw ConfigError(fmt::format(
        "{}: JSON nested deeper than {} levels: not a model file", source, kMaxJsonDepth));
  }
  Json doc;
  try {
    doc = Json::parse(text);
  } catch (const Json::parse_error& e) {
    throw ConfigError(fmt::format(
        "{}: not valid JSON (truncated or corrupted?) at byte {}: {}", source, e.byte, e.what()));
  } catch (const Json::exception& e) {  // e.g. a number too large for a double
    throw ConfigError(source + ": not valid JSON: " + e.what());
  }
  if (!doc.is_object()) {
    throw ConfigError(source + ": a model file is a JSON object, got " + Reader::describe(doc));
  }
  return doc;
}

/// Reads the `conditions` object `c` (every key present; null: unknown) into `out`.
void read_conditions(const Json& c, const Reader& r, std::size_t n_out, TrainingConditions& out) {
  r.only_keys(c,
              "conditions",
              {"pa_mm_s2", "aa_mm_s2", "dwell_s", "smoothing_s", "axis", "machine", "noise_floor"});
  const auto range = [&](const char* name) -> std::optional<ConditionRange> {
    const Json& v = r.key(c, "conditions", name);
    if (v.is_null()) return std::nullopt;
    const std::string at = std::string("conditions.") + name;
    const Json& o = r.object(c, "conditions", name);
    r.only_keys(o, at, {"lo", "hi"});
    return ConditionRange{r.number(o, at, "lo"), r.number(o, at, "hi")};
  };
  out.pa_mm_s2 = range("pa_mm_s2");
  out.aa_mm_s2 = range("aa_mm_s2");
  const auto number = [&](const char* name) -> std::optional<double> {
    const Json& v = r.key(c, "conditions", name);
    if (v.is_null()) return std::nullopt;
    return r.number(c, "conditions", name);
  };
  out.dwell_s = number("dwell_s");
  out.smoothing_s = number("smoothing_s");
  const auto text = [&](const char* name) -> std::string {
    const Json& v = r.key(c, "conditions", name);
    if (v.is_null()) return {};
    std::string s = r.string(c, "conditions", name);
    if (s.empty()) r.fail(std::string("conditions.") + name + " is empty (write null: unknown)");
    return s;
  };
  out.axis = text("axis");
  out.machine = text("machine");
  if (!r.key(c, "conditions", "noise_floor").is_null()) {
    const Json& floor = r.array(c, "conditions", "noise_floor", n_out);
    for (std::size_t o = 0; o < n_out; ++o) {
      out.noise_floor.push_back(
          r.number(floor[o], "conditions.noise_floor" + idx(static_cast<int>(o))));
    }
  }
}

/// The file's format_version (kModelFileVersion, kModelFileVersionNoCornerGain or
/// kModelFileVersionNoUncertainty).
int read_version(const Json& doc, const Reader& r) {
  const auto version = doc.find("format_version");
  if (version == doc.end()) {
    r.fail(fmt::format("missing key 'format_version' (this library reads versions {} to {})",
                       kModelFileVersionNoUncertainty,
                       kModelFileVersion));
  }
  const bool known =
      version->is_number_integer() && (version->get<long long>() == kModelFileVersion ||
                                       version->get<long long>() == kModelFileVersionNoConditions ||
                                       version->get<long long>() == kModelFileVersionNoCornerGain ||
                                       version->get<long long>() == kModelFileVersionNoUncertainty);
  if (!known) {
    r.fail(fmt::format("format_version {} is not supported (this library reads versions {} to {})",
                       version->dump(),
                       kModelFileVersionNoUncertainty,
                       kModelFileVersion));
  }
  return static_cast<int>(version->get<long long>());
}

ModelArchitecture read_header(const Json& doc, const Reader& r) {
  const std::string format = r.string(doc, "", "format");
  if (format != kModelFileFormat) {
    r.fail("format is '" + format + "', expected '" + kModelFileFormat + "'");
  }
  read_version(doc, r);
  const Json& arch = r.object(doc, "", "architecture");
  r.only_keys(arch,
              "architecture",
              {"inputs",
               "sets_per_input",
               "outputs",
               "rules",
               "parameter_count",
               "membership",
               "consequent"});
  const auto positive = [&](const char* name, long long max) {
    const long long v = r.integer(arch, "architecture", name);
    if (v < 1 || v > max) r.fail(fmt::format("architecture.{} = {} is out of range", name, v));
    return static_cast<int>(v);
  };
  ModelArchitecture a;
  a.inputs = positive("inputs", 32);
  a.sets_per_input = positive("sets_per_input", 1 << 20);
  a.outputs = positive("outputs", 1 << 20);
  const int rules = rules_of(a.inputs, a.sets_per_input);
  if (rules < 0) r.fail("architecture: more than 2^20 rules");
  const long long file_rules = r.integer(arch, "architecture", "rules");
  if (file_rules != rules) {
    r.fail(
        fmt::format("architecture.rules = {} but sets_per_input^inputs = {}", file_rules, rules));
  }
  const long long count = r.integer(arch, "architecture", "parameter_count");
  const long long expected = 2LL * a.inputs * a.sets_per_input +
                             static_cast<long long>(a.outputs) * rules * (a.inputs + 1);
  if (count != expected) {
    r.fail(fmt::format("architecture.parameter_count = {} but the sizes give {}", count, expected));
  }
  const std::string membership = r.string(arch, "architecture", "membership");
  if (membership != "gaussian") {
    r.fail("architecture.membership is '" + membership + "', only 'gaussian' is supported");
  }
  const std::string consequent = r.string(arch, "architecture", "consequent");
  if (consequent != "first-order") {
    r.fail("architecture.consequent is '" + consequent + "', only 'first-order' is supported");
  }
  return a;
}

/// Finds the first key that occurs twice in an object (the parser would keep only the last), and
/// the first floating-point number whose text is not what `dump()` writes for its value.
/// The checksum covers values; this makes it cover the text too, so an edit that keeps the value
/// (e.g. the 17th digit of a number) is still caught. Integers have one spelling already.
class CanonicalNumbers {
 public:
  using number_integer_t = Json::number_integer_t;
  using number_unsigned_t = Json::number_unsigned_t;
  using number_float_t = Json::number_float_t;
  using string_t = Json::string_t;
  using binary_t = Json::binary_t;

  bool null() { return value(); }
  bool boolean(bool /*unused*/) { return value(); }
  bool number_integer(number_integer_t /*unused*/) { return value(); }
  bool number_unsigned(number_unsigned_t /*unused*/) { return value(); }
  bool number_float(number_float_t v, const string_t& text) {
    if (bad_text.empty()) {
      std::string canonical = Json(v).dump();
      if (text != canonical) {
        bad_text = text;
        bad_canonical = std::move(canonical);
        bad_path = path();
      }
    }
    return value();
  }
  bool string(string_t& /*unused*/) { return value(); }
  bool binary(binary_t& /*unused*/) { return value(); }
  bool start_object(std::size_t /*unused*/) {
    frames_.push_back({false, 0, {}, {}});
    return true;
  }
  bool key(string_t& k) {
    Frame& f = frames_.back();
    f.key = k;
    if (!f.keys.insert(k).second && duplicate_path.empty()) duplicate_path = path();
    return true;
  }
  bool end_object() {
    frames_.pop_back();
    return value();
  }
  bool start_array(std::size_t /*unused*/) {
    frames_.push_back({true, 0, {}, {}});
    return true;
  }
  bool end_array() {
    frames_.pop_back();
    return value();
  }
  bool parse_error(std::size_t /*unused*/,
                   const std::string& /*unused*/,
                   const nlohmann::detail::exception& /*unused*/) {
    return false;  // cannot happen: the text was parsed before
  }

  std::string bad_text, bad_canonical, bad_path;
  std::string duplicate_path;  ///< first key that occurs twice in one object

 private:
  struct Frame {
    bool array;
    std::size_t index;
    std::string key;
    std::set<std::string> keys;
  };
  bool value() {
    if (!frames_.empty() && frames_.back().array) ++frames_.back().index;
    return true;
  }
  std::string path() const {
    std::string p;
    for (const Frame& f : frames_) {
      if (f.array) {
        p += "[" + std::to_string(f.index) + "]";
      } else {
        p += (p.empty() ? "" : ".") + f.key;
      }
    }
    return p;
  }
  std::vector<Frame> frames_;
};

}  // namespace

namespace detail {

void check_model_data(const ModelData& data, const std::string& where) {
  check_sizes(data);
  check_content(data, where);
}

std::string content_checksum(const ModelData& data) { return checksum_of(to_json<Json>(data)); }

std::string format_model_json(const ModelData& data) {
  check_sizes(data);
  check_content(data, "model to write");
  OrderedJson doc = to_json<OrderedJson>(data);
  doc["checksum"] = checksum_of(to_json<Json>(data));
  std::string out;
  write_pretty(doc, 0, out);
  out += "\n";
  return out;
}

ModelData parse_model_json(const std::string& text,
                           const std::string& source,
                           const ModelArchitecture& expected) {
  const Json doc = parse_document(text, source);
  const Reader r(source);
  const int version = read_version(doc, r);
  // Version 1 has no "uncertainty" (its slot in the list repeats "checksum": no extra key);
  // versions 2 to 4 require it (null: no calibration). Versions before 4 have no "conditions".
  const bool v1 = version == kModelFileVersionNoUncertainty;
  const bool has_conditions = version >= kModelFileVersion;
  r.only_keys(doc,
              "",
              {"format",
               "format_version",
               "architecture",
               "inputs",
               "outputs",
               "parameters",
               "training",
               has_conditions ? "conditions" : "checksum",
               v1 ? "checksum" : "uncertainty",
               "checksum"});
  if (!v1) {
    r.key(doc, "", "uncertainty");  // required in version 2 (null: no calibration)
  }
  const ModelArchitecture a = read_header(doc, r);
  if (a.inputs != expected.inputs || a.sets_per_input != expected.sets_per_input ||
      a.outputs != expected.outputs) {
    r.fail(fmt::format(
        "architecture is {} inputs x {} sets x {} outputs, but this program expects {} x {} x {}",
        a.inputs,
        a.sets_per_input,
        a.outputs,
        expected.inputs,
        expected.sets_per_input,
        expected.outputs));
  }
  ModelData d;
  d.inputs = a.inputs;
  d.sets = a.sets_per_input;
  d.outputs = a.outputs;
  const auto n_in = static_cast<std::size_t>(d.inputs);
  const auto n_out = static_cast<std::size_t>(d.outputs);

  const Json& inputs = r.array(doc, "", "inputs", n_in);
  for (std::size_t i = 0; i < n_in; ++i) {
    const std::string at = "inputs" + idx(static_cast<int>(i));
    const Json& in = inputs[i];
    if (!in.is_object()) r.fail(at + " must be an object, got " + Reader::describe(in));
    r.only_keys(in, at, {"name", "unit", "lo", "hi"});
    d.input_names.push_back(r.string(in, at, "name"));
    d.input_units.push_back(r.string(in, at, "unit"));
    fuzzy::InputRange range;
    range.lo = r.number(in, at, "lo");
    range.hi = r.number(in, at, "hi");
    d.ranges.push_back(range);
  }
  const Json& outputs = r.array(doc, "", "outputs", n_out);
  for (std::size_t o = 0; o < n_out; ++o) {
    const std::string at = "outputs" + idx(static_cast<int>(o));
    const Json& out = outputs[o];
    if (!out.is_object()) r.fail(at + " must be an object, got " + Reader::describe(out));
    r.only_keys(out, at, {"name", "unit"});
    d.output_names.push_back(r.string(out, at, "name"));
    d.output_units.push_back(r.string(out, at, "unit"));
  }

  const Json& params = r.object(doc, "", "parameters");
  r.only_keys(params, "parameters", {"centres", "widths", "consequents"});
  d.params.assign(static_cast<std::size_t>(param_count(d.inputs, d.sets, d.outputs)), 0.0);
  const auto n_sets = static_cast<std::size_t>(d.sets);
  const Json& centres = r.array(params, "parameters", "centres", n_in);
  const Json& widths = r.array(params, "parameters", "widths", n_in);
  for (int i = 0; i < d.inputs; ++i) {
    const auto u = static_cast<std::size_t>(i);
    const std::string ci = "parameters.centres" + idx(i);
    const std::string wi = "parameters.widths" + idx(i);
    const Json& c = r.sized(centres[u], ci, n_sets);
    const Json& w = r.sized(widths[u], wi, n_sets);
    for (int s = 0; s < d.sets; ++s) {
      const auto v = static_cast<std::size_t>(s);
      d.params[centre_index(d, i, s)] = r.number(c[v], ci + idx(s));
      d.params[width_index(d, i, s)] = r.number(w[v], wi + idx(s));
    }
  }
  const int rules = rules_of(d.inputs, d.sets);
  const Json& consequents = r.array(params, "parameters", "consequents", n_out);
  for (int o = 0; o < d.outputs; ++o) {
    const std::string co = "parameters.consequents" + idx(o);
    const Json& block =
        r.sized(consequents[static_cast<std::size_t>(o)], co, static_cast<std::size_t>(rules));
    for (int j = 0; j < rules; ++j) {
      const std::string cj = co + idx(j);
      const Json& rule = r.sized(block[static_cast<std::size_t>(j)], cj, n_in + 1);
      for (int k = 0; k <= d.inputs; ++k) {
        d.params[consequent_index(d, o, j, k)] =
            r.number(rule[static_cast<std::size_t>(k)], cj + idx(k));
      }
    }
  }

  const Json& training = r.object(doc, "", "training");
  r.only_keys(
      training,
      "training",
      {"data_file_sha256", "method", "lambda", "cv_rmse", "trained_at", "seed", "tool_version"});
  ModelMetadata& t = d.training;
  t.data_file_sha256 = r.string(training, "training", "data_file_sha256");
  t.method = r.string(training, "training", "method");
  t.lambda = r.number(training, "training", "lambda");
  const Json& cv = r.array(training, "training", "cv_rmse", n_out);
  for (std::size_t o = 0; o < n_out; ++o) {
    t.cv_rmse.push_back(r.number(cv[o], "training.cv_rmse" + idx(static_cast<int>(o))));
  }
  t.trained_at = r.string(training, "training", "trained_at");
  t.seed = r.unsigned_integer(training, "training", "seed");
  t.tool_version = r.string(training, "training", "tool_version");

  if (has_conditions) read_conditions(r.object(doc, "", "conditions"), r, n_out, d.conditions);

  d.format_version = version;
  const auto uncertainty = doc.find("uncertainty");
  if (uncertainty != doc.end() && !uncertainty->is_null()) {
    const Json& u = r.object(doc, "", "uncertainty");
    // Version 2 has no corner_gain (its slot repeats "method": no extra key); version 3 needs it.
    const bool v2 = version == kModelFileVersionNoCornerGain;
    r.only_keys(u,
                "uncertainty",
                {"coverage",
                 "half_width",
                 "extrapolation_gain",
                 v2 ? "method" : "corner_gain",
                 "method",
                 "calibration_samples"});
    d.interval_coverage = r.number(r.key(u, "uncertainty", "coverage"), "uncertainty.coverage");
    if (d.interval_coverage == 0)
      r.fail("uncertainty.coverage = 0 (write null for no calibration)");
    const Json& hw = r.array(u, "uncertainty", "half_width", n_out);
    const Json& gain = r.array(u, "uncertainty", "extrapolation_gain", n_out);
    for (std::size_t o = 0; o < n_out; ++o) {
      d.interval_half_width.push_back(
          r.number(hw[o], "uncertainty.half_width" + idx(static_cast<int>(o))));
      d.interval_gain.push_back(
          r.number(gain[o], "uncertainty.extrapolation_gain" + idx(static_cast<int>(o))));
    }
    if (v2) {
      d.interval_corner_gain.assign(n_out, 0.0);
    } else {
      const Json& corner = r.array(u, "uncertainty", "corner_gain", n_out);
      for (std::size_t o = 0; o < n_out; ++o) {
        d.interval_corner_gain.push_back(
            r.number(corner[o], "uncertainty.corner_gain" + idx(static_cast<int>(o))));
      }
    }
    d.interval_method = r.string(u, "uncertainty", "method");
    d.interval_samples = r.unsigned_integer(u, "uncertainty", "calibration_samples");
  }

  check_content(d, source);

  d.checksum = r.string(doc, "", "checksum");
  if (!is_lower_hex(d.checksum, 64)) {
    r.fail("checksum '" + d.checksum + "' is not 64 lower-case hex digits (SHA-256)");
  }
  Json content = doc;
  content.erase("checksum");
  const std::string actual = checksum_of(content);
  if (actual != d.checksum) {
    r.fail("checksum mismatch: the file says " + d.checksum + " but its content hashes to " +
           actual + " (the file was modified or corrupted after it was written)");
  }
  CanonicalNumbers canonical;
  Json::sax_parse(text, &canonical);
  if (!canonical.duplicate_path.empty()) {
    r.fail("key '" + canonical.duplicate_path + "' occurs twice in its object");
  }
  if (!canonical.bad_text.empty()) {
    r.fail(canonical.bad_path + ": number '" + canonical.bad_text +
           "' is not written as this library writes its value ('" + canonical.bad_canonical +
           "'): the file was edited after it was written (the checksum covers the canonical text)");
  }
  return d;
}

}  // namespace detail

ModelArchitecture read_model_architecture(const std::string& text, const std::string& source) {
  const Json doc = parse_document(text, source);
  return read_header(doc, Reader(source));
}

std::string utc_timestamp_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  std::array<char, 32> buf{};
  std::strftime(buf.data(), buf.size(), "%Y-%m-%dT%H:%M:%SZ", &utc);
  return buf.data();
}

}  // namespace cmmcomp::io
