// SPDX-License-Identifier: MIT
/// @file The versioned JSON model file: writing, validation, checksum, constexpr header export.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/error.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>

namespace cmmcomp::io {
namespace {

using Json = nlohmann::json;                 // keys sorted: the canonical form for the checksum
using OrderedJson = nlohmann::ordered_json;  // keys in writing order: the file a human reads

// ---------------------------------------------------------------------------------------------
// SHA-256 (FIPS 180-4). Small and dependency-free; speed is irrelevant for model files.

class Sha256 {
 public:
  void update(const unsigned char* p, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      block_[fill_++] = p[i];
      if (fill_ == 64) {
        compress();
        fill_ = 0;
      }
    }
    length_ += n;
  }
  std::string hex() {
    const std::uint64_t bits = length_ * 8u;
    const unsigned char pad = 0x80;
    update(&pad, 1);
    const unsigned char zero = 0;
    while (fill_ != 56) update(&zero, 1);
    for (int i = 7; i >= 0; --i) {
      const auto b = static_cast<unsigned char>(bits >> (8 * i));
      update(&b, 1);
    }
    std::string out;
    for (std::uint32_t v : h_) out += fmt::format("{:08x}", v);
    return out;
  }

 private:
  static std::uint32_t rotr(std::uint32_t x, int n) { return (x >> n) | (x << (32 - n)); }
  void compress() {
    static constexpr std::array<std::uint32_t, 64> k = {
        0x428a2f98, 0x71374491, 0xb5c0fbcf, 0xe9b5dba5, 0x3956c25b, 0x59f111f1, 0x923f82a4,
        0xab1c5ed5, 0xd807aa98, 0x12835b01, 0x243185be, 0x550c7dc3, 0x72be5d74, 0x80deb1fe,
        0x9bdc06a7, 0xc19bf174, 0xe49b69c1, 0xefbe4786, 0x0fc19dc6, 0x240ca1cc, 0x2de92c6f,
        0x4a7484aa, 0x5cb0a9dc, 0x76f988da, 0x983e5152, 0xa831c66d, 0xb00327c8, 0xbf597fc7,
        0xc6e00bf3, 0xd5a79147, 0x06ca6351, 0x14292967, 0x27b70a85, 0x2e1b2138, 0x4d2c6dfc,
        0x53380d13, 0x650a7354, 0x766a0abb, 0x81c2c92e, 0x92722c85, 0xa2bfe8a1, 0xa81a664b,
        0xc24b8b70, 0xc76c51a3, 0xd192e819, 0xd6990624, 0xf40e3585, 0x106aa070, 0x19a4c116,
        0x1e376c08, 0x2748774c, 0x34b0bcb5, 0x391c0cb3, 0x4ed8aa4a, 0x5b9cca4f, 0x682e6ff3,
        0x748f82ee, 0x78a5636f, 0x84c87814, 0x8cc70208, 0x90befffa, 0xa4506ceb, 0xbef9a3f7,
        0xc67178f2};
    std::array<std::uint32_t, 64> w{};
    for (std::size_t t = 0; t < 16; ++t) {
      w[t] = (std::uint32_t{block_[4 * t]} << 24) | (std::uint32_t{block_[4 * t + 1]} << 16) |
             (std::uint32_t{block_[4 * t + 2]} << 8) | std::uint32_t{block_[4 * t + 3]};
    }
    for (std::size_t t = 16; t < 64; ++t) {
      const std::uint32_t s0 = rotr(w[t - 15], 7) ^ rotr(w[t - 15], 18) ^ (w[t - 15] >> 3);
      const std::uint32_t s1 = rotr(w[t - 2], 17) ^ rotr(w[t - 2], 19) ^ (w[t - 2] >> 10);
      w[t] = w[t - 16] + s0 + w[t - 7] + s1;
    }
    std::array<std::uint32_t, 8> v = h_;
    for (std::size_t t = 0; t < 64; ++t) {
      const std::uint32_t s1 = rotr(v[4], 6) ^ rotr(v[4], 11) ^ rotr(v[4], 25);
      const std::uint32_t ch = (v[4] & v[5]) ^ (~v[4] & v[6]);
      const std::uint32_t t1 = v[7] + s1 + ch + k[t] + w[t];
      const std::uint32_t s0 = rotr(v[0], 2) ^ rotr(v[0], 13) ^ rotr(v[0], 22);
      const std::uint32_t maj = (v[0] & v[1]) ^ (v[0] & v[2]) ^ (v[1] & v[2]);
      const std::uint32_t t2 = s0 + maj;
      v = {t1 + t2, v[0], v[1], v[2], v[3] + t1, v[4], v[5], v[6]};
    }
    for (std::size_t i = 0; i < 8; ++i) h_[i] += v[i];
  }

  std::array<std::uint32_t, 8> h_ = {0x6a09e667,
                                     0xbb67ae85,
                                     0x3c6ef372,
                                     0xa54ff53a,
                                     0x510e527f,
                                     0x9b05688c,
                                     0x1f83d9ab,
                                     0x5be0cd19};
  std::array<unsigned char, 64> block_{};
  std::size_t fill_ = 0;
  std::uint64_t length_ = 0;
};

// ---------------------------------------------------------------------------------------------
// Shared checks and helpers.

int rules_of(int inputs, int sets) {
  const int r = fuzzy::detail::checked_pow(sets, inputs);
  return r;
}
int param_count(int inputs, int sets, int outputs) {
  return 2 * inputs * sets + outputs * rules_of(inputs, sets) * (inputs + 1);
}
// Flat indices; must equal TskLayout's (tests compare them through the typed accessors).
std::size_t centre_index(const detail::ModelData& d, int i, int s) {
  return static_cast<std::size_t>(s * d.inputs + i);
}
std::size_t width_index(const detail::ModelData& d, int i, int s) {
  return static_cast<std::size_t>(d.inputs * d.sets + s * d.inputs + i);
}
std::size_t consequent_index(const detail::ModelData& d, int o, int j, int k) {
  return static_cast<std::size_t>(2 * d.inputs * d.sets + (j * d.outputs + o) * (d.inputs + 1) + k);
}

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

ModelArchitecture read_header(const Json& doc, const Reader& r) {
  const std::string format = r.string(doc, "", "format");
  if (format != kModelFileFormat) {
    r.fail("format is '" + format + "', expected '" + kModelFileFormat + "'");
  }
  const auto version = doc.find("format_version");
  if (version == doc.end()) {
    r.fail(fmt::format("missing key 'format_version' (this library reads version {})",
                       kModelFileVersion));
  }
  if (!version->is_number_integer() || version->get<long long>() != kModelFileVersion) {
    r.fail(fmt::format("format_version {} is not supported (this library reads version {})",
                       version->dump(),
                       kModelFileVersion));
  }
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

std::string double_literal(double v) {
  std::array<char, 40> buf{};
  std::snprintf(buf.data(), buf.size(), "%.17g", v);
  std::string s(buf.data());
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s;
}

// The float nearest to `v`, in the shortest text that reads back as that float, as a C float
// literal: what a float model's exported source holds (fuzzy::convert_model's rounding).
std::string float_literal(double v) {
  std::string s = fmt::format("{}", static_cast<float>(v));
  if (s.find_first_of(".eEn") == std::string::npos) s += ".0";
  return s + "f";
}

bool is_identifier(const std::string& s) {
  if (s.empty() || (s[0] >= '0' && s[0] <= '9')) return false;
  return std::all_of(s.begin(), s.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '_';
  });
}

}  // namespace

namespace detail {

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
  r.only_keys(doc,
              "",
              {"format",
               "format_version",
               "architecture",
               "inputs",
               "outputs",
               "parameters",
               "training",
               "checksum"});
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

// The flat parameter block in its own order (tsk_params.hpp), one literal per value: set-major
// centres and widths, then the consequents rule by rule, every output of a rule together.
template <typename Literal>
void append_flat_block(std::string& h, const ModelData& data, Literal&& literal) {
  const int rules = rules_of(data.inputs, data.sets);
  for (int s = 0; s < data.sets; ++s) {
    h += "         // centres of set " + std::to_string(s) + ", inputs 0.." +
         std::to_string(data.inputs - 1) + "\n        ";
    for (int i = 0; i < data.inputs; ++i)
      h += " " + literal(data.params[centre_index(data, i, s)]) + ",";
    h += "\n";
  }
  for (int s = 0; s < data.sets; ++s) {
    h += "         // widths of set " + std::to_string(s) + ", inputs 0.." +
         std::to_string(data.inputs - 1) + "\n        ";
    for (int i = 0; i < data.inputs; ++i)
      h += " " + literal(data.params[width_index(data, i, s)]) + ",";
    h += "\n";
  }
  h += "         // consequents [rule][output][term 0 = constant, 1 + i = input i]\n";
  for (int j = 0; j < rules; ++j) {
    for (int o = 0; o < data.outputs; ++o) {
      h += "        ";
      for (int k = 0; k <= data.inputs; ++k) {
        h += " " + literal(data.params[consequent_index(data, o, j, k)]) + ",";
      }
      h += "  // rule " + std::to_string(j) + ", output " + std::to_string(o) + "\n";
    }
  }
}

std::string export_model_header(const ModelData& data,
                                const std::string& symbol_name,
                                bool single) {
  if (!is_identifier(symbol_name)) {
    throw ConfigError("export_model_header: symbol name '" + symbol_name +
                      "' is not a C identifier");
  }
  check_sizes(data);
  check_content(data, "model to export");
  const std::string checksum = checksum_of(to_json<Json>(data));
  const std::string id = checksum.substr(0, 16);
  const int rules = rules_of(data.inputs, data.sets);
  const ModelMetadata& t = data.training;
  std::string h;
  auto out = std::back_inserter(h);
  fmt::format_to(out,
                 "// SPDX-License-Identifier: MIT\n"
                 "// clang-format off\n"
                 "/// @file T-S model {0}, generated by cmmcomp::io::export_model_header. Do not "
                 "edit.\n"
                 "///\n"
                 "/// Model file format {1} version {2} (docs/model-file.md).\n"
                 "/// checksum (SHA-256): {3}\n"
                 "/// architecture: {4} inputs x {5} gaussian sets, {6} rules, first-order "
                 "consequents, {7} outputs, {8} parameters\n"
                 "/// inputs (normalised over [lo, hi]):\n",
                 id,
                 kModelFileFormat,
                 kModelFileVersion,
                 checksum,
                 data.inputs,
                 data.sets,
                 rules,
                 data.outputs,
                 param_count(data.inputs, data.sets, data.outputs));
  for (std::size_t i = 0; i < data.input_names.size(); ++i) {
    fmt::format_to(out,
                   "///   {}: name \"{}\", unit [{}], lo {}, hi {}\n",
                   i,
                   data.input_names[i],
                   data.input_units[i],
                   double_literal(data.ranges[i].lo),
                   double_literal(data.ranges[i].hi));
  }
  fmt::format_to(out, "/// outputs:\n");
  for (std::size_t o = 0; o < data.output_names.size(); ++o) {
    fmt::format_to(out,
                   "///   {}: name \"{}\", unit [{}], cv_rmse {}\n",
                   o,
                   data.output_names[o],
                   data.output_units[o],
                   double_literal(t.cv_rmse[o]));
  }
  fmt::format_to(
      out,
      "/// training: method \"{}\", lambda {}, seed {}, trained_at {}, tool \"{}\", "
      "data_file_sha256 \"{}\"\n"
      "#pragma once\n\n"
      "#include <cmmcomp/fuzzy/tsk_evaluator.hpp>\n\n"
      "/// Model id: first 16 hex digits of the checksum.\n"
      "inline constexpr char {}_model_id[] = \"{}\";\n"
      "/// SHA-256 of the model file content (docs/model-file.md, checksum rule).\n"
      "inline constexpr char {}_checksum[] = \"{}\";\n\n"
      "/// The network{}; evaluate it with cmmcomp::fuzzy::evaluate.\n"
      "inline constexpr cmmcomp::fuzzy::TskModel<{}, {}, {}, {}> {} = {{\n"
      "    // ranges {{lo, hi}} of each input\n"
      "    {{{{\n",
      t.method,
      double_literal(t.lambda),
      t.seed,
      t.trained_at,
      t.tool_version,
      t.data_file_sha256,
      symbol_name,
      id,
      symbol_name,
      checksum,
      single ? " in float (each parameter the float nearest the model file's double)" : "",
      single ? "float" : "double",
      data.inputs,
      data.sets,
      data.outputs,
      symbol_name);
  for (const fuzzy::InputRange& r : data.ranges) {
    fmt::format_to(out, "        {{{}, {}}},\n", double_literal(r.lo), double_literal(r.hi));
  }
  h += "    }},\n"
       "    // parameters: empty TskLayout base, then the flat block (layout in tsk_params.hpp)\n"
       "    {{},\n"
       "     {{\n";
  if (single) {
    append_flat_block(h, data, float_literal);
  } else {
    append_flat_block(h, data, double_literal);
  }
  h += "     }}}};\n"
       "// clang-format on\n";
  return h;
}

std::string export_model_c_source(const ModelData& data,
                                  const std::string& symbol_name,
                                  bool single) {
  if (!is_identifier(symbol_name)) {
    throw ConfigError("export_model_c_source: symbol name '" + symbol_name +
                      "' is not a C identifier");
  }
  check_sizes(data);
  check_content(data, "model to export");
  if (data.sets != 3 || data.outputs != 4 || (data.inputs != 4 && data.inputs != 5)) {
    throw ConfigError(
        "export_model_c_source: the firmware C ABI serves 4- or 5-input, 3-set, "
        "4-output models");
  }
  const std::string checksum = checksum_of(to_json<Json>(data));
  const std::string id = checksum.substr(0, 16);
  std::string h;
  auto out = std::back_inserter(h);
  fmt::format_to(
      out,
      "/* SPDX-License-Identifier: MIT */\n"
      "/* clang-format off */\n"
      "/* T-S model {0} for the firmware C ABI (cmmcomp/compensator_fw.h), generated by\n"
      " * cmmcomp::io::export_model_c_source. Do not edit.\n"
      " * Model file format {1} version {2}; checksum (SHA-256) {3}.\n"
      " * {4} inputs x 3 gaussian sets, 4 outputs; parameters in {5}. */\n"
      "#include <cmmcomp/compensator_fw.h>\n\n"
      "#if CMMCOMP_FW_INPUTS != {4}\n"
      "#error \"this model has {4} inputs: build with CMMCOMP_FW_INPUTS={4}\"\n"
      "#endif\n"
      "/* The parameters are {5}: the build must say CMMCOMP_FW_SCALAR={5}. */\n"
      "typedef char {6}_scalar_is_{5}[sizeof(CMMCOMP_FW_SCALAR) == {7} ? 1 : -1];\n\n"
      "/* Model id: first 16 hex digits of the checksum (cmmcomp_fw_publish's model_id). */\n"
      "const uint64_t {6}_id = 0x{0}u;\n\n"
      "const cmmcomp_fw_model {6} = {{\n"
      "    /* ranges {{lo, hi}} of each input */\n"
      "    {{\n",
      id,
      kModelFileFormat,
      kModelFileVersion,
      checksum,
      data.inputs,
      single ? "float" : "double",
      symbol_name,
      single ? 4 : 8);
  for (std::size_t i = 0; i < data.ranges.size(); ++i) {
    fmt::format_to(out,
                   "        {{{}, {}}},  /* {} [{}] */\n",
                   double_literal(data.ranges[i].lo),
                   double_literal(data.ranges[i].hi),
                   data.input_names[i],
                   data.input_units[i]);
  }
  h += "    },\n"
       "    /* parameters: the flat block (layout in tsk_params.hpp) */\n"
       "    {\n";
  if (single) {
    append_flat_block(h, data, float_literal);
  } else {
    append_flat_block(h, data, double_literal);
  }
  h += "    }};\n"
       "/* clang-format on */\n";
  // The block's comments are C++ style: rewrite them for C99's sake of style consistency.
  std::string c;
  c.reserve(h.size());
  for (std::size_t pos = 0; pos < h.size();) {
    const std::size_t slash = h.find("// ", pos);
    const std::size_t eol = h.find('\n', pos);
    if (slash != std::string::npos && slash < eol) {
      c.append(h, pos, slash - pos);
      c += "/* " + h.substr(slash + 3, eol - slash - 3) + " */";
      pos = eol;
    } else {
      const std::size_t end = eol == std::string::npos ? h.size() : eol + 1;
      c.append(h, pos, end - pos);
      pos = end;
    }
  }
  return c;
}

std::string read_text_file(const std::string& path, const char* what) {
  return read_file_bounded(path, what, kMaxModelFileBytes);
}

void write_text_file(const std::string& path, const std::string& text) {
  write_file_atomically(path, text);
}

}  // namespace detail

ModelArchitecture read_model_architecture(const std::string& text, const std::string& source) {
  const Json doc = parse_document(text, source);
  return read_header(doc, Reader(source));
}

std::string sha256_hex(const std::string& bytes) {
  Sha256 h;
  h.update(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size());
  return h.hex();
}

std::string sha256_file_hex(const std::string& path) {
  return sha256_hex(read_file_bounded(path, "file", kMaxTextFileBytes));
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
