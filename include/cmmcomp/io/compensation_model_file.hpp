// SPDX-License-Identifier: MIT
/// @file Loads a model file for the compensator, whichever of its two architectures it has:
/// the paper's 4 inputs (PV, PD, AV, AD) or 5 with the carriage position Y.
///
/// The compensator feeds its inputs by position, so a file is accepted only when its input and
/// output names are exactly those `io::set_paper_names` writes (what cmmcomp-train produces);
/// anything else is a ConfigError that says which name differs.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <string>
#include <variant>

namespace cmmcomp::io {

using PaperModelFile = ModelFile<4, 3, 4>;   ///< inputs PV, PD, AV, AD
using PaperModelFileY = ModelFile<5, 3, 4>;  ///< inputs PV, PD, AV, AD, Y
/// A model file the compensator can serve.
using CompensationModelFile = std::variant<PaperModelFile, PaperModelFileY>;

/// Parses and validates `text` (`source` names it in messages) as either architecture. Setup
/// only. Throws ConfigError as parse_model_json, or when the architecture is neither 4 × 3 × 4
/// nor 5 × 3 × 4, or when a name differs from set_paper_names'.
CompensationModelFile parse_compensation_model(const std::string& text, const std::string& source);

/// Reads and parses a file as parse_compensation_model.
CompensationModelFile load_compensation_model(const std::string& path);

/// The model id (first 16 hex digits of the checksum) as the number the compensator echoes.
std::uint64_t numeric_model_id(const CompensationModelFile& file);

/// The model id as the file names it (16 hex digits).
const std::string& model_id(const CompensationModelFile& file);

/// Inputs of the file's network: 4 or 5.
int model_inputs(const CompensationModelFile& file);

/// Publishes the file's network into `axis` of `compensator` with numeric_model_id(file).
/// Returns what MoveCompensator::publish returns.
Status publish(compensation::MoveCompensator& compensator,
               int axis,
               const CompensationModelFile& file,
               std::string* why = nullptr);

}  // namespace cmmcomp::io
