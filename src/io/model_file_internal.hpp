// SPDX-License-Identifier: MIT
/// @file What src/io/model_header_export.cpp needs from the JSON side of the model file. Not
/// installed.
#pragma once

#include <cmmcomp/io/model_file.hpp>
#include <cstddef>
#include <string>

namespace cmmcomp::io::detail {

/// The flat layout's index arithmetic for `d`'s sizes: TskLayout's own formula.
inline fuzzy::RuntimeLayout layout_of(const ModelData& d) { return {d.inputs, d.sets, d.outputs}; }
inline int rules_of(int inputs, int sets) { return fuzzy::RuntimeLayout{inputs, sets, 1}.rules(); }
inline int param_count(int inputs, int sets, int outputs) {
  return fuzzy::RuntimeLayout{inputs, sets, outputs}.param_count();
}
inline std::size_t centre_index(const ModelData& d, int i, int s) {
  return static_cast<std::size_t>(layout_of(d).centre_index(i, s));
}
inline std::size_t width_index(const ModelData& d, int i, int s) {
  return static_cast<std::size_t>(layout_of(d).width_index(i, s));
}
inline std::size_t consequent_index(const ModelData& d, int o, int j, int k) {
  return static_cast<std::size_t>(layout_of(d).consequent_index(o, j, k));
}

/// Throws ConfigError "where: ..." when `data` would not load back (format_model_json's checks).
void check_model_data(const ModelData& data, const std::string& where);

/// The checksum the file of `data` carries (docs/model-file.md, "Checksum"), 64 hex digits.
std::string content_checksum(const ModelData& data);

}  // namespace cmmcomp::io::detail
