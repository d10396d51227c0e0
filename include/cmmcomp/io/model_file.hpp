// SPDX-License-Identifier: MIT
/// @file The versioned JSON model file of a trained T-S network, and its constexpr C++ export.
///
/// Format (docs/model-file.md): one JSON object with `format` = "cmmcomp-tsk-model",
/// `format_version` = 3, `architecture`, `inputs` (names, units, normalisation ranges),
/// `outputs`, `parameters` (centres, widths and consequents as nested arrays, same order as the
/// flat layout of tsk_params.hpp), `training` metadata, `conditions` (what the model was trained
/// at that is not an input: accelerations, controller timing, axis, machine, noise floor),
/// `uncertainty` (the prediction interval's
/// calibration, or null; docs/uncertainty.md), and `checksum`: the SHA-256 (lower-case
/// hex) of the compact, key-sorted serialisation of the object without `checksum`. Loading
/// validates everything and throws ConfigError "source: where: what is wrong".
///
/// Everything here is Setup only (allocates, may throw). The JSON library stays inside
/// src/io/model_file_json.cpp (the header export is src/io/model_header_export.cpp, the checksum
/// src/io/sha256.cpp); the templates below only convert to and from a runtime struct.
#pragma once

#include <array>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <cmmcomp/io/sha256.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cmmcomp::io {

/// `format` of every model file.
inline constexpr const char* kModelFileFormat = "cmmcomp-tsk-model";
/// `format_version` this library writes. It reads this one, kModelFileVersionNoConditions,
/// kModelFileVersionNoCornerGain and kModelFileVersionNoUncertainty.
inline constexpr int kModelFileVersion = 4;
/// The third format version: no `conditions`; still read, with every condition unknown.
inline constexpr int kModelFileVersionNoConditions = 3;
/// The second format version: `uncertainty` without `corner_gain`; still read, with every corner
/// gain 0 (the interval as version 2 defined it).
inline constexpr int kModelFileVersionNoCornerGain = 2;
/// The first format version, without `uncertainty`: still read, as a model with no interval
/// calibration (its Corrections carry kFlagNoUncertainty).
inline constexpr int kModelFileVersionNoUncertainty = 1;

/// How a model was trained (the `training` object). Informational: nothing here changes how the
/// model evaluates, but it is covered by the checksum.
struct ModelMetadata {
  /// SHA-256 of the training data file, 64 lower-case hex digits (`sha256_file_hex`), or empty
  /// when the model did not come from a file.
  std::string data_file_sha256;
  std::string method;           ///< training method, free text (e.g. "ceres-lm"); non-empty
  double lambda = 0.0;          ///< regularisation weight, finite, >= 0
  std::vector<double> cv_rmse;  ///< cross-validated RMSE per output (one per output, >= 0)
  std::string trained_at;       ///< ISO-8601 UTC, `YYYY-MM-DDTHH:MM:SS[.fff]Z`
  std::uint64_t seed = 0;       ///< random seed of the training run
  std::string tool_version;     ///< version of the tool that trained it; non-empty

  bool operator==(const ModelMetadata& o) const {
    return data_file_sha256 == o.data_file_sha256 && method == o.method && lambda == o.lambda &&
           cv_rmse == o.cv_rmse && trained_at == o.trained_at && seed == o.seed &&
           tool_version == o.tool_version;
  }
  bool operator!=(const ModelMetadata& o) const { return !(*this == o); }
};

/// A closed range of a training condition: lo <= hi, both finite (a single value: lo == hi).
struct ConditionRange {
  double lo = 0.0;
  double hi = 0.0;
  bool operator==(const ConditionRange& o) const { return lo == o.lo && hi == o.hi; }
  bool operator!=(const ConditionRange& o) const { return !(*this == o); }
};

/// What a model was trained at that is not one of its inputs (the `conditions` object, format
/// 4; docs/model-file.md, "Conditions"). Every field may be unknown: a file of format 3 or
/// older has none, and a trainer records only what its data or its user tell it. Covered by the
/// checksum. The compensator refuses or flags a move whose PA or AA lies outside a known range
/// (compensation/conditions.hpp); cmmcomp-plan plans with these values.
struct TrainingConditions {
  /// Positioning accelerations PA of the training moves [mm/s²], lo > 0; none: unknown.
  std::optional<ConditionRange> pa_mm_s2;
  /// Approach accelerations AA of the training moves [mm/s²], lo > 0; none: unknown.
  std::optional<ConditionRange> aa_mm_s2;
  /// The controller's dwell [s] (the stop between positioning and approach), >= 0.
  std::optional<double> dwell_s;
  /// The controller's acceleration smoothing [s] (S-curve jerk time), >= 0.
  std::optional<double> smoothing_s;
  std::string axis;     ///< the moving axis the moves were taken on ("x", …); empty: unknown
  std::string machine;  ///< the machine's name (its machine file's `name`); empty: unknown
  /// The campaign's noise floor per output [same unit as the output] (the repeatability σ of
  /// each parameter, e.g. from cmmcomp-measure extract's summary), >= 0; empty: unknown.
  std::vector<double> noise_floor;

  /// True when nothing is known (a format-3 file).
  bool unknown() const {
    return !pa_mm_s2 && !aa_mm_s2 && !dwell_s && !smoothing_s && axis.empty() && machine.empty() &&
           noise_floor.empty();
  }
  bool operator==(const TrainingConditions& o) const {
    return pa_mm_s2 == o.pa_mm_s2 && aa_mm_s2 == o.aa_mm_s2 && dwell_s == o.dwell_s &&
           smoothing_s == o.smoothing_s && axis == o.axis && machine == o.machine &&
           noise_floor == o.noise_floor;
  }
  bool operator!=(const TrainingConditions& o) const { return !(*this == o); }
};

/// Sizes stored in a file's `architecture` (see `read_model_architecture`).
struct ModelArchitecture {
  int inputs = 0;          ///< inputs of the network
  int sets_per_input = 0;  ///< Gaussian sets per input
  int outputs = 0;         ///< outputs (consequent blocks)
};

/// A model file in memory: the network with its ranges, names, units and training metadata.
/// Any sizes work; a compensation model's file is a ModelFileOf<Inputs>
/// (compensation_model_file.hpp), which fills the names from the schema.
template <int kInputs, int kSets, int kOutputs>
struct ModelFile {
  using Model = fuzzy::TskModel<double, kInputs, kSets, kOutputs>;
  Model model{};                                     ///< ranges (raw units) and parameters
  std::array<std::string, kInputs> input_names{};    ///< unique, non-empty (e.g. "pv_mm_s")
  std::array<std::string, kInputs> input_units{};    ///< unit of each input (e.g. "mm/s")
  std::array<std::string, kOutputs> output_names{};  ///< unique, non-empty (e.g. "mpe_um")
  std::array<std::string, kOutputs> output_units{};  ///< unit of each output (e.g. "um")
  ModelMetadata training{};                          ///< how it was trained
  TrainingConditions conditions{};                   ///< what it was trained at (`conditions`)
  /// The prediction interval's calibration (`uncertainty`); not available() when the file has
  /// none (`uncertainty` null, or format version 1).
  fuzzy::IntervalCalibration<kOutputs> interval{};
  /// How `interval` was calibrated (free text, non-empty when available), and from how many
  /// samples (> 0 when available). Informational, covered by the checksum.
  std::string interval_method;
  std::uint64_t interval_samples = 0;
  /// The file's `format_version` (filled by parse/load; files are always written in
  /// kModelFileVersion).
  int format_version = kModelFileVersion;
  /// SHA-256 of the content (64 hex). Filled by parse/load; ignored when writing (recomputed).
  std::string checksum;
  /// First 16 hex digits of `checksum`: names the model in logs. Filled by parse/load.
  std::string model_id;
};

namespace detail {

/// Size-erased form of ModelFile, the interface to src/io/model_file_json.cpp and
/// src/io/model_header_export.cpp. Not API.
struct ModelData {
  int inputs = 0;
  int sets = 0;
  int outputs = 0;
  std::vector<std::string> input_names, input_units, output_names, output_units;
  std::vector<fuzzy::InputRange> ranges;
  std::vector<double> params;  ///< flat layout of tsk_params.hpp
  ModelMetadata training;
  TrainingConditions conditions;
  double interval_coverage = 0;  ///< 0: no calibration (then the vectors are empty)
  std::vector<double> interval_half_width, interval_gain, interval_corner_gain;
  std::string interval_method;
  std::uint64_t interval_samples = 0;
  int format_version = kModelFileVersion;
  std::string checksum;
};

std::string format_model_json(const ModelData& data);
ModelData parse_model_json(const std::string& text,
                           const std::string& source,
                           const ModelArchitecture& expected);
std::string export_model_header(const ModelData& data, const std::string& symbol_name, bool single);
std::string export_model_c_source(const ModelData& data,
                                  const std::string& symbol_name,
                                  bool single);
/// A model file's text: a bounded read (io::read_file_bounded, kMaxModelFileBytes).
inline std::string read_text_file(const std::string& path, const char* what) {
  return read_file_bounded(path, what, kMaxModelFileBytes);
}

template <int kInputs, int kSets, int kOutputs>
ModelData to_data(const ModelFile<kInputs, kSets, kOutputs>& file) {
  ModelData d;
  d.inputs = kInputs;
  d.sets = kSets;
  d.outputs = kOutputs;
  d.input_names.assign(file.input_names.begin(), file.input_names.end());
  d.input_units.assign(file.input_units.begin(), file.input_units.end());
  d.output_names.assign(file.output_names.begin(), file.output_names.end());
  d.output_units.assign(file.output_units.begin(), file.output_units.end());
  d.ranges.assign(file.model.ranges.begin(), file.model.ranges.end());
  d.params.assign(file.model.params.values.begin(), file.model.params.values.end());
  d.training = file.training;
  d.conditions = file.conditions;
  if (file.interval.available()) {
    d.interval_coverage = file.interval.coverage;
    d.interval_half_width.assign(file.interval.half_width.begin(), file.interval.half_width.end());
    d.interval_gain.assign(file.interval.extrapolation_gain.begin(),
                           file.interval.extrapolation_gain.end());
    d.interval_corner_gain.assign(file.interval.corner_gain.begin(),
                                  file.interval.corner_gain.end());
    d.interval_method = file.interval_method;
    d.interval_samples = file.interval_samples;
  }
  return d;
}

template <int kInputs, int kSets, int kOutputs>
ModelFile<kInputs, kSets, kOutputs> from_data(const ModelData& d) {
  ModelFile<kInputs, kSets, kOutputs> f;
  for (std::size_t i = 0; i < static_cast<std::size_t>(kInputs); ++i) {
    f.input_names[i] = d.input_names[i];
    f.input_units[i] = d.input_units[i];
    f.model.ranges[i] = d.ranges[i];
  }
  for (std::size_t o = 0; o < static_cast<std::size_t>(kOutputs); ++o) {
    f.output_names[o] = d.output_names[o];
    f.output_units[o] = d.output_units[o];
  }
  for (std::size_t k = 0; k < f.model.params.values.size(); ++k) {
    f.model.params.values[k] = d.params[k];
  }
  f.training = d.training;
  f.conditions = d.conditions;
  if (d.interval_coverage > 0) {
    f.interval.coverage = d.interval_coverage;
    for (std::size_t o = 0; o < static_cast<std::size_t>(kOutputs); ++o) {
      f.interval.half_width[o] = d.interval_half_width[o];
      f.interval.extrapolation_gain[o] = d.interval_gain[o];
      f.interval.corner_gain[o] = d.interval_corner_gain[o];
    }
    f.interval_method = d.interval_method;
    f.interval_samples = d.interval_samples;
  }
  f.format_version = d.format_version;
  f.checksum = d.checksum;
  f.model_id = d.checksum.substr(0, 16);
  return f;
}

}  // namespace detail

/// The model file text (UTF-8 JSON, 2-space indent, numbers round-trip exact, checksum
/// computed). Setup only. Throws ConfigError if `file` would not load back: model not valid
/// (`fuzzy::validate`), an empty or duplicate name, `training.cv_rmse` not one finite value >= 0
/// per output, a malformed `trained_at` or `data_file_sha256`, a negative or non-finite lambda,
/// an empty method or tool version, a condition out of its range (a PA or AA range with lo <= 0
/// or lo > hi, a negative dwell or smoothing, a noise floor not one finite value >= 0 per output,
/// a control character in the axis or machine), an interval calibration that is not valid
/// (fuzzy::validate_interval) or available without a method or samples.
template <int kInputs, int kSets, int kOutputs>
std::string format_model_json(const ModelFile<kInputs, kSets, kOutputs>& file) {
  return detail::format_model_json(detail::to_data(file));
}

/// Parses and validates model file text; `source` names it in messages. The file's
/// architecture must be kInputs × kSets × kOutputs. Setup only. Throws ConfigError naming the
/// source, the key path and the problem: not JSON (with byte offset), wrong `format`, missing or
/// unsupported `format_version` (1 to 4 are read; 1 has no `uncertainty`, 2 no `corner_gain`, 3
/// no `conditions`),
/// architecture mismatch
/// (both stated), a missing or unknown key, a wrong type or array length, a non-finite number,
/// width <= 0, lo >= hi, a checksum mismatch, or a number not written in the canonical form this
/// library writes (an edit that kept the value; see docs/model-file.md).
template <int kInputs, int kSets, int kOutputs>
ModelFile<kInputs, kSets, kOutputs> parse_model_json(const std::string& text,
                                                     const std::string& source) {
  return detail::from_data<kInputs, kSets, kOutputs>(
      detail::parse_model_json(text, source, ModelArchitecture{kInputs, kSets, kOutputs}));
}

/// Reads and parses a model file. Setup only. Throws ConfigError "path: cannot open model file"
/// or as parse_model_json.
template <int kInputs, int kSets, int kOutputs>
ModelFile<kInputs, kSets, kOutputs> load_model_file(const std::string& path) {
  return parse_model_json<kInputs, kSets, kOutputs>(detail::read_text_file(path, "model file"),
                                                    path);
}

/// Writes `format_model_json(file)` to `path` (replacing it). Setup only. Throws as
/// format_model_json, or Error when the file cannot be written. Returns the model id (first 16
/// hex digits of the checksum).
template <int kInputs, int kSets, int kOutputs>
std::string save_model_file(const std::string& path,
                            const ModelFile<kInputs, kSets, kOutputs>& file) {
  const std::string text = format_model_json(file);
  write_file_atomically(path, text);
  return parse_model_json<kInputs, kSets, kOutputs>(text, path).model_id;
}

/// A self-contained C++17 header for firmware without a file system. It includes only
/// <cmmcomp/fuzzy/tsk_evaluator.hpp> and defines, at global scope,
///   inline constexpr cmmcomp::fuzzy::TskModel<double, I, S, O> <symbol_name> = {...};
///   inline constexpr char <symbol_name>_model_id[] = "...";   // 16 hex
///   inline constexpr char <symbol_name>_checksum[] = "...";   // 64 hex (SHA-256)
/// with every double written round-trip exact (`%.17g`), and names, units, ranges and training
/// metadata as comments. The text depends only on the content (deterministic). Setup only.
/// Throws ConfigError if `symbol_name` is not a C identifier, or as format_model_json.
/// With `single`, the model is a TskModel<float, …> whose parameters are each the float nearest
/// the file's double (the values fuzzy::convert_model<float> gives), for an MCU's float path.
template <int kInputs, int kSets, int kOutputs>
std::string export_model_header(const ModelFile<kInputs, kSets, kOutputs>& file,
                                const std::string& symbol_name,
                                bool single = false) {
  return detail::export_model_header(detail::to_data(file), symbol_name, single);
}

/// A C99 source defining `const cmmcomp_fw_model <symbol_name>` and `<symbol_name>_id` for the
/// firmware C ABI (cmmcomp/compensator_fw.h): ranges in double, parameters in float when
/// `single` (each the float nearest the double, as fuzzy::convert_model rounds) or in double
/// (exact). It refuses to compile against a CMMCOMP_FW_INPUTS or CMMCOMP_FW_SCALAR other than
/// the model's. Deterministic. Setup only. Throws ConfigError for a model the firmware ABI does
/// not serve (other than 4 or 5 inputs, 3 sets, 4 outputs), or as export_model_header.
template <int kInputs, int kSets, int kOutputs>
std::string export_model_c_source(const ModelFile<kInputs, kSets, kOutputs>& file,
                                  const std::string& symbol_name,
                                  bool single) {
  return detail::export_model_c_source(detail::to_data(file), symbol_name, single);
}

/// The sizes in a model file's `architecture`, to choose the ModelFile type to parse it with.
/// Validates only JSON syntax, `format`, `format_version` and `architecture`. Setup only;
/// throws ConfigError.
ModelArchitecture read_model_architecture(const std::string& text, const std::string& source);

/// The current time as ISO-8601 UTC with whole seconds, `YYYY-MM-DDTHH:MM:SSZ`.
std::string utc_timestamp_now();

}  // namespace cmmcomp::io
