// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the measurement files a user hands to cmmcomp-measure
/// (docs/measurement.md). The first byte picks the reader: 'P' plan.csv (parse_plan_csv),
/// anything else the I++ program (parse_ipp_program). Any ConfigError is a correct answer. An
/// accepted plan must be in run order, and writing it and reading it back must give the same
/// text; an accepted program's points must be finite.
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cmmcomp::measure;
  if (size == 0) return 0;
  const std::string text(reinterpret_cast<const char*>(data) + 1, size - 1);
  try {
    if (data[0] == 'P') {
      const std::vector<PlannedMove> plan = parse_plan_csv(text, "fuzz-plan.csv");
      for (std::size_t i = 0; i < plan.size(); ++i) {
        if (plan[i].run_order != static_cast<int>(i) + 1) std::abort();
        if (plan[i].direction != 1 && plan[i].direction != -1) std::abort();
      }
      const std::string written = format_plan_csv(plan);
      if (format_plan_csv(parse_plan_csv(written, "fuzz-written.csv")) != written) std::abort();
    } else {
      for (const IppPoint& p : parse_ipp_program(text, "fuzz.ipp")) {
        if (!std::isfinite(p.point.x + p.point.y + p.point.z + p.meas_speed + p.approach)) {
          std::abort();
        }
      }
    }
  } catch (const cmmcomp::ConfigError&) {
    return 0;
  }
  return 0;
}
