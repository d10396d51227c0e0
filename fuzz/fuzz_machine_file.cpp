// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the machine file reader (dynamics::parse_machine), as cmmcomp-sim
/// and cmmcomp-train read it: the subset check, then toml++, then the key and range checks.
/// Any ConfigError is a correct answer. An accepted machine must be physical, and writing it
/// and reading it back must give the same machine, its capabilities included (the writer stays
/// inside the subset, and a format-2 file's fixed timing reads back inside its capabilities).
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cmmcomp::dynamics;
  const std::string text(reinterpret_cast<const char*>(data), size);
  Machine m;
  try {
    m = parse_machine(text, "fuzz.toml");
  } catch (const cmmcomp::ConfigError&) {
    return 0;
  }
  if (!is_physical(m.parameters, nullptr)) std::abort();
  const Machine back = parse_machine(format_machine(m), "fuzz-written.toml");  // must not throw
  if (back.name != m.name || back.description != m.description) std::abort();
  for (const auto& info : machine_parameter_table()) {
    if (info.get(back.parameters) != info.get(m.parameters)) std::abort();
  }
  for (const auto& info : cmmcomp::motion::kSettings) {
    if (back.capabilities[info.setting].min != m.capabilities[info.setting].min ||
        back.capabilities[info.setting].max != m.capabilities[info.setting].max) {
      std::abort();
    }
  }
  return 0;
}
