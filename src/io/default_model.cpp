// SPDX-License-Identifier: MIT
/// @file The compiled-in default model (data/models/default.json, embedded at build time).
#include <cmmcomp/io/default_model.hpp>
#include <utility>
#include <variant>

#include "default_model_json.inc"  // kDefaultModelJson, generated from data/models/default.json

namespace cmmcomp::io {

ModelFileOf<PaperInputs> default_model_file() {
  auto any = parse_compensation_model(kDefaultModelJson, kDefaultModelSource);
  // The build embeds data/models/default.json, the paper's inputs (test_default_model).
  return std::get<ModelFileOf<PaperInputs>>(std::move(any));
}

}  // namespace cmmcomp::io
