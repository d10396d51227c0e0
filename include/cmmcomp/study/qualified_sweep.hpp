// SPDX-License-Identifier: MIT
/// @file The length test's speed-up over a qualified machine, measured on the twin
/// (docs/planner.md, "The qualified reference"; docs/study.md).
///
/// At every setting of a grid (PV, PD, AV, AD; PA 200, AA 60) and for every noise seed, the
/// virtual controller runs its length test (vc::run_length_test) with the uncompensated columns
/// qualified (a static reversal map and the probe qualified per setting) and the compensated
/// column corrected by a model served in the same process (vc::LocalSource, as cmmcomp-agent
/// serves it). A setting *passes* for a kind when every Y of the program meets MPE_E for every
/// seed. The result: each setting's time per point and passes, the fastest setting of each kind
/// and their ratio, the headline's "X× less time per point than the fastest qualified
/// uncompensated setting that meets the same MPE_E", with the twin itself as the judge.
/// Targets: some qualified uncompensated setting passes, some compensated setting passes, and
/// compensation is not slower (ratio ≥ 1). Setup-time code: allocates, simulates; throws
/// ConfigError for an empty grid, no seed or a model that cannot be published.
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace cmmcomp::study {

/// The grid of fast settings [mm/s, mm]; every combination is run.
struct SweepGrid {
  std::vector<double> pv_mm_s{76.75, 100};
  std::vector<double> pd_mm{40, 50, 60};
  std::vector<double> av_mm_s{12, 14, 16};
  std::vector<double> ad_mm{5, 6, 7, 8, 9, 10};
};

/// One setting of the grid and what the seeds found.
struct SweepSetting {
  double pv_mm_s = 0, pd_mm = 0, av_mm_s = 0, ad_mm = 0;
  double time_per_point_s = 0;
  int uncompensated_passes = 0;  ///< seeds at which every Y met MPE_E, qualified uncompensated
  int compensated_passes = 0;    ///< the same, compensated by the model
};

struct SweepResult {
  std::string model_id;
  std::vector<std::uint64_t> seeds;
  std::vector<SweepSetting> settings;  ///< in grid order (PV, then PD, AV, AD)
  /// Indices into `settings` of the fastest setting passing every seed (grid order breaks ties).
  std::optional<std::size_t> fastest_uncompensated, fastest_compensated;
  double speedup = 0;  ///< fastest uncompensated time / fastest compensated time; 0 without both
  std::vector<Target> targets;
};

/// Runs the sweep (file comment) of `model` on `machine` (its controller's dwell and smoothing
/// count in every point's time).
SweepResult qualified_sweep(const io::CompensationModelFile& model,
                            const dynamics::Machine& machine,
                            const std::vector<std::uint64_t>& seeds,
                            const SweepGrid& grid = {},
                            const RunOptions& options = {});

}  // namespace cmmcomp::study
