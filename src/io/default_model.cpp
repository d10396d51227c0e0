// SPDX-License-Identifier: MIT
/// @file The compiled-in default model (data/models/default.json, embedded at build time).
#include <cmmcomp/io/default_model.hpp>

#include "default_model_json.inc"  // kDefaultModelJson, generated from data/models/default.json

namespace cmmcomp::io {

ModelFile<4, 3, 4> default_model_file() {
  return parse_model_json<4, 3, 4>(kDefaultModelJson, kDefaultModelSource);
}

}  // namespace cmmcomp::io
