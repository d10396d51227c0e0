// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the dataset CSV reader (io/dataset_csv.hpp), as cmmcomp-train and
/// cmmcomp-sim anova feed it. Every accepted row must hold finite values only.
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto rows = cmmcomp::io::parse_dataset_csv(text, "fuzz.csv");
    for (const auto& r : rows) {
      if (!std::isfinite(r.pv_mm_s) || !std::isfinite(r.rae_um)) std::abort();
    }
  } catch (const cmmcomp::ConfigError&) {
  }
  return 0;
}
