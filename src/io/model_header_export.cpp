// SPDX-License-Identifier: MIT
/// @file A model file's network as source code: the constexpr C++ header and the C99 source of
/// the firmware ABI, deterministic and round-trip exact.
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cstdio>
#include <optional>
#include <string>

#include "model_file_internal.hpp"

namespace cmmcomp::io {
namespace {

using detail::centre_index;
using detail::consequent_index;
using detail::param_count;
using detail::rules_of;
using detail::width_index;

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

/// The interval calibration's values of `data` as a brace list, in IntervalCalibration's (and
/// cmmcomp_fw_interval_calibration's) member order: coverage, then half_width,
/// extrapolation_gain and corner_gain, one entry per output; all 0 when the file has none.
/// `{{lo, hi}, {lo, hi}}` of the PA and AA conditions ({0, 0}: unknown), for both exports.
std::string conditions_initialiser(const detail::ModelData& data) {
  const auto range = [](const std::optional<ConditionRange>& r) {
    return r ? fmt::format("{{{}, {}}}", double_literal(r->lo), double_literal(r->hi))
             : std::string("{0.0, 0.0}");
  };
  return "{" + range(data.conditions.pa_mm_s2) + ", " + range(data.conditions.aa_mm_s2) + "}";
}

/// One comment line with every training condition, "unknown" for those the file lacks.
std::string conditions_comment(const detail::ModelData& data) {
  const TrainingConditions& c = data.conditions;
  const auto range = [](const std::optional<ConditionRange>& r) {
    return r ? fmt::format("{}..{}", double_literal(r->lo), double_literal(r->hi))
             : std::string("unknown");
  };
  const auto value = [](const std::optional<double>& v) {
    return v ? double_literal(*v) : std::string("unknown");
  };
  const auto text = [](const std::string& v) { return v.empty() ? std::string("unknown") : v; };
  return fmt::format(
      "conditions: PA {} mm/s2, AA {} mm/s2, dwell {} s, smoothing {} s, axis {}, machine {}",
      range(c.pa_mm_s2),
      range(c.aa_mm_s2),
      value(c.dwell_s),
      value(c.smoothing_s),
      text(c.axis),
      text(c.machine));
}

std::string interval_initialiser(const detail::ModelData& data) {
  const auto list = [&](const std::vector<double>& v) {
    std::string s = "{";
    for (int o = 0; o < data.outputs; ++o) {
      const double x = v.empty() ? 0.0 : v[static_cast<std::size_t>(o)];
      s += (o == 0 ? "" : ", ") + double_literal(x);
    }
    return s + "}";
  };
  return "{" + double_literal(data.interval_coverage) + ", " + list(data.interval_half_width) +
         ", " + list(data.interval_gain) + ", " + list(data.interval_corner_gain) + "}";
}

}  // namespace

namespace detail {

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
  check_model_data(data, "model to export");
  const std::string checksum = content_checksum(data);
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
      "/// {}\n"
      "#pragma once\n\n"
      "#include <cmmcomp/compensation/conditions.hpp>\n"
      "#include <cmmcomp/fuzzy/prediction_interval.hpp>\n"
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
      conditions_comment(data),
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
  h += "     }}}};\n\n";
  fmt::format_to(out,
                 "/// The model file's interval calibration (docs/uncertainty.md; coverage 0: "
                 "none): publish it with the\n"
                 "/// network (StaticMoveCompensator::publish(axis, network, interval, id)).\n"
                 "inline constexpr cmmcomp::fuzzy::IntervalCalibration<{}> {}_interval = {};\n",
                 data.outputs,
                 symbol_name,
                 interval_initialiser(data));
  fmt::format_to(out,
                 "/// The PA and AA the model was trained at ({{0, 0}}: unknown; "
                 "compensation/conditions.hpp):\n"
                 "/// publish them with the network (StaticMoveCompensator::publish(axis, "
                 "network, interval, conditions, id)).\n"
                 "inline constexpr cmmcomp::compensation::Conditions {}_conditions = {};\n",
                 symbol_name,
                 conditions_initialiser(data));
  h += "// clang-format on\n";
  return h;
}

std::string export_model_c_source(const ModelData& data,
                                  const std::string& symbol_name,
                                  bool single) {
  if (!is_identifier(symbol_name)) {
    throw ConfigError("export_model_c_source: symbol name '" + symbol_name +
                      "' is not a C identifier");
  }
  check_model_data(data, "model to export");
  if (data.sets != 3 || data.outputs != 4 || (data.inputs != 4 && data.inputs != 5)) {
    throw ConfigError(
        "export_model_c_source: the firmware C ABI serves 4- or 5-input, 3-set, "
        "4-output models");
  }
  const std::string checksum = content_checksum(data);
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
  h += "    }};\n\n";
  fmt::format_to(out,
                 "/* The model file's interval calibration (docs/uncertainty.md; coverage 0: "
                 "none), for\n"
                 " * cmmcomp_fw_publish_with_interval. */\n"
                 "const cmmcomp_fw_interval_calibration {}_interval = {};\n\n",
                 symbol_name,
                 interval_initialiser(data));
  fmt::format_to(out,
                 "/* The model file's training conditions ({{0, 0}}: unknown), for\n"
                 " * cmmcomp_fw_publish_with_conditions; {}. */\n"
                 "const cmmcomp_fw_conditions {}_conditions = {};\n",
                 conditions_comment(data),
                 symbol_name,
                 conditions_initialiser(data));
  h += "/* clang-format on */\n";
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
}  // namespace detail

}  // namespace cmmcomp::io
