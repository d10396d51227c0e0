// SPDX-License-Identifier: MIT
/// @file Simulates many probing moves in parallel into dataset rows (docs/dataset-csv.md).
#pragma once

#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/noise.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/schema.hpp>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// How to simulate a dataset.
struct DatasetOptions {
  MeasurementNoise noise{};        ///< off by default; sample i gets noise stream i
  int threads = 0;                 ///< worker threads; 0 = all hardware threads
  SimulationOptions simulation{};  ///< per-move integration settings
  /// Called on the calling thread about every 100 ms and at the end: (done, total).
  std::function<void(std::size_t, std::size_t)> progress;
};

/// Simulates every row's move (its pv/pd/av/ad/pa/aa/y columns, file units) and fills its four
/// error columns. The result does not depend on the thread count. Throws Error naming the row
/// (1-based) whose move is invalid or whose simulation failed.
std::vector<DatasetRow> simulate_dataset(const Machine& machine,
                                         std::vector<DatasetRow> rows,
                                         const DatasetOptions& options);

/// The move of a dataset row (file units mm, mm/s, mm/s²) in SI units, without a jerk limit.
inline motion::ProbingMove move_of(const DatasetRow& r) {
  return motion::probing_move_mm(r.pv_mm_s, r.pa_mm_s2, r.pd_mm, r.av_mm_s, r.aa_mm_s2, r.ad_mm);
}

/// The fixed settings of a design's moves, file units (mm, mm/s, mm/s²).
struct FixedSettings {
  double pa_mm_s2 = paper::kBaseline.pa_mm_s2;  ///< positioning acceleration
  double aa_mm_s2 = paper::kBaseline.aa_mm_s2;  ///< approach acceleration
  double y_mm = paper::kBaseline.y_mm;          ///< carriage position
};

/// Rows (errors zero) for a design whose factors are named PV, PD, AV, AD in SI units (as
/// doe::paper_table3_factors()), optionally with Y (carriage position [m]; without it every row
/// gets fixed.y_mm); other factors are rejected with ConfigError.
std::vector<DatasetRow> rows_from_design(const doe::Design& design, const FixedSettings& fixed);

}  // namespace cmmcomp::dynamics
