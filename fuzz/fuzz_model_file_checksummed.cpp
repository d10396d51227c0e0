// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the model file reader past its checksum. Random bytes almost never
/// carry a valid SHA-256, so the structure checks behind it would go unexplored: when the input
/// is a JSON object, this target recomputes `checksum` by the documented rule
/// (docs/model-file.md) before parsing.
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::string text(reinterpret_cast<const char*>(data), size);
  // The target's own parse is bounded like the reader's, so that it does not find the deep
  // nesting the reader refuses (and which nlohmann's recursive dump cannot take).
  if (size > 1u << 20) return 0;
  int depth = 0;
  for (const char c : text) {
    depth += (c == '[' || c == '{') ? 1 : 0;
    if (depth > 32) return 0;
  }
  nlohmann::json doc = nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/false);
  if (doc.is_object()) {
    doc.erase("checksum");
    doc["checksum"] = cmmcomp::io::sha256_hex(doc.dump());
    text = doc.dump(2);
  }
  try {
    (void)cmmcomp::io::parse_compensation_model(text, "fuzz.json");
  } catch (const cmmcomp::ConfigError&) {
  }
  return 0;
}
