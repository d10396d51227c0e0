// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the model file reader (io/compensation_model_file.hpp) on raw bytes,
/// as cmmcomp-agent, cmmcomp-train and the C ABI feed it. Any ConfigError is a correct answer;
/// a crash, a sanitizer report or another exception is a finding.
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cstddef>
#include <cstdint>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto file = cmmcomp::io::parse_compensation_model(text, "fuzz.json");
    (void)cmmcomp::io::model_inputs(file);
  } catch (const cmmcomp::ConfigError&) {
  }
  return 0;
}
