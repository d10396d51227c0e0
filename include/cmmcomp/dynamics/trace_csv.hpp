// SPDX-License-Identifier: MIT
/// @file The trace CSV of a simulated move (`cmmcomp-sim move --trace FILE`): one row per
/// integrator output, the commanded, scale and tip positions and the error (docs/machine-model.md,
/// "The trace CSV").
#pragma once

#include <array>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// The header row's columns, in order, with the TraceSample field each one writes.
struct TraceColumn {
  const char* name;
  double TraceSample::*field;
};
inline constexpr std::array<TraceColumn, 7> kTraceColumns = {{
    {"t_s", &TraceSample::t_s},
    {"commanded_mm", &TraceSample::commanded_mm},
    {"scale_mm", &TraceSample::scale_mm},
    {"tip_mm", &TraceSample::tip_mm},
    {"error_um", &TraceSample::error_um},
    {"velocity_mm_s", &TraceSample::velocity_mm_s},
    {"acceleration_mm_s2", &TraceSample::acceleration_mm_s2},
}};

/// The CSV text: the header, then every sample with 9 significant digits. Setup only.
std::string format_trace_csv(const std::vector<TraceSample>& trace);

}  // namespace cmmcomp::dynamics
