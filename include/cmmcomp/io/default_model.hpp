// SPDX-License-Identifier: MIT
/// @file The project's shipped default compensation model, compiled in.
///
/// data/models/default.json: the paper's 4-input, 4-output network (schema.hpp's PaperInputs)
/// trained on the DEFAULT DIGITAL TWIN (data/machines/default.toml), by
/// scripts/train-default-model.sh. It describes the simulated machine, not a real one: a real
/// machine needs a model trained on its own measurements. cmmcomp-agent serves it when no --model
/// is given (and says so).
#pragma once

#include <cmmcomp/io/compensation_model_file.hpp>

namespace cmmcomp::io {

/// The default model, parsed and validated from the compiled-in copy of
/// data/models/default.json. Setup only (allocates).
ModelFileOf<PaperInputs> default_model_file();

/// Where the compiled-in default model came from, for log messages.
inline constexpr const char* kDefaultModelSource = "data/models/default.json (compiled in)";

}  // namespace cmmcomp::io
