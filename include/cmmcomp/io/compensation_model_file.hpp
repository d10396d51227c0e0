// SPDX-License-Identifier: MIT
/// @file Model files keyed on their input set, and loading one for the compensator whichever of
/// the served input sets (schema.hpp, ServedInputSets) it has.
///
/// The compensator feeds a model's inputs by position, so a file is accepted only when its
/// input and output names and units are exactly its set's columns and units in schema.hpp
/// (what cmmcomp-train writes); anything else is a ConfigError that says which name differs.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <string>
#include <utility>
#include <variant>

namespace cmmcomp::io {

/// The model file of a compensation model of input set `Inputs`: a ModelFile whose names and
/// units are the schema's (filled by the default constructor), with the set in its type.
template <typename Inputs>
struct ModelFileOf
    : ModelFile<Inputs::kCount, compensation::kSetsPerInput, compensation::kModelOutputs> {
  using InputSet = Inputs;
  using File = ModelFile<Inputs::kCount, compensation::kSetsPerInput, compensation::kModelOutputs>;

  /// An empty model with the schema's names and units.
  ModelFileOf() {
    const auto columns = Inputs::columns();
    const auto units = Inputs::units();
    for (std::size_t i = 0; i < columns.size(); ++i) {
      this->input_names[i] = columns[i];
      this->input_units[i] = units[i];
    }
    for (std::size_t o = 0; o < kErrors.size(); ++o) {
      this->output_names[o] = kErrors[o].column;
      this->output_units[o] = kErrors[o].unit;
    }
  }
  /// `file` as a file of `Inputs`; the caller has checked its names (schema_name_problem).
  explicit ModelFileOf(File file) : File(std::move(file)) {}

  /// The compensation model it holds.
  compensation::Model<Inputs> compensation_model() const {
    return compensation::Model<Inputs>(this->model);
  }
};

/// Why `file`'s names or units are not the schema's for `Inputs` ("input 4 is 'z_mm'; the
/// compensator feeds 'y_mm' there"), or an empty string.
template <typename Inputs>
std::string schema_name_problem(const typename ModelFileOf<Inputs>::File& file) {
  const ModelFileOf<Inputs> want;
  const auto check = [](const auto& got, const auto& expected, const char* what) -> std::string {
    for (std::size_t k = 0; k < expected.size(); ++k) {
      if (got[k] != expected[k]) {
        return std::string(what) + " " + std::to_string(k) + " is '" + got[k] +
               "'; the compensator feeds '" + expected[k] + "' there";
      }
    }
    return {};
  };
  for (std::string p : {check(file.input_names, want.input_names, "input"),
                        check(file.input_units, want.input_units, "unit of input"),
                        check(file.output_names, want.output_names, "output"),
                        check(file.output_units, want.output_units, "unit of output")}) {
    if (!p.empty()) return p;
  }
  return {};
}

/// Parses `text` as a model file of `Inputs` (parse_model_json, then schema_name_problem).
/// Setup only. Throws ConfigError as parse_model_json, or naming the first name that differs.
template <typename Inputs>
ModelFileOf<Inputs> parse_model_file_of(const std::string& text, const std::string& source) {
  auto file =
      parse_model_json<Inputs::kCount, compensation::kSetsPerInput, compensation::kModelOutputs>(
          text, source);
  const std::string problem = schema_name_problem<Inputs>(file);
  if (!problem.empty()) throw ConfigError(source + ": " + problem);
  return ModelFileOf<Inputs>(std::move(file));
}

/// Reads and parses a model file of `Inputs` as parse_model_file_of.
template <typename Inputs>
ModelFileOf<Inputs> load_model_file_of(const std::string& path) {
  return parse_model_file_of<Inputs>(detail::read_text_file(path, "model file"), path);
}

/// A model file of any served input set.
template <typename... Sets>
using AnyModelFileOf = std::variant<ModelFileOf<Sets>...>;
using CompensationModelFile = apply_input_sets<AnyModelFileOf, ServedInputSets>::type;

/// Parses and validates `text` (`source` names it in messages) as a model of one of the served
/// input sets, chosen by its names. Setup only. Throws ConfigError as parse_model_json, or when
/// no served set has the file's architecture, or when a name differs from its set's.
CompensationModelFile parse_compensation_model(const std::string& text, const std::string& source);

/// Reads and parses a file as parse_compensation_model.
CompensationModelFile load_compensation_model(const std::string& path);

/// The model id (first 16 hex digits of the checksum) as the number the compensator echoes.
std::uint64_t numeric_model_id(const CompensationModelFile& file);

/// The model id as the file names it (16 hex digits).
const std::string& model_id(const CompensationModelFile& file);

/// Number of inputs of the file's network.
int model_inputs(const CompensationModelFile& file);

/// The conditions the compensator checks (PA and AA; compensation/conditions.hpp) from a
/// file's `conditions`: unknown ones stay unknown.
compensation::Conditions compensation_conditions(const TrainingConditions& conditions);

/// The file's training conditions (all unknown for a format-3 or older file).
const TrainingConditions& training_conditions(const CompensationModelFile& file);

/// The coverage of the interval every interface of the compensator reports (its half-widths
/// are U95: Correction::u95_um, the C ABI's cmmcomp_interval, Modbus, CAN).
inline constexpr double kServedCoverage = 0.95;

/// Publishes the file's network, its interval calibration (none for a format-1 file) and its
/// training conditions (compensation_conditions) into `axis` of `compensator` with
/// numeric_model_id(file). A file whose interval is calibrated at another coverage than
/// kServedCoverage is refused (kInvalidInput, `why` says so): its half-widths are not U95.
/// Returns what MoveCompensator::publish returns.
Status publish(compensation::MoveCompensator& compensator,
               int axis,
               const CompensationModelFile& file,
               std::string* why = nullptr);

/// As publish, at whatever coverage the file's interval was calibrated: for a consumer in the
/// same process that reads the coverage from the file and states it (the feed planner), never
/// for an interface that labels the half-widths U95.
Status publish_at_its_coverage(compensation::MoveCompensator& compensator,
                               int axis,
                               const CompensationModelFile& file,
                               std::string* why = nullptr);

}  // namespace cmmcomp::io
