// SPDX-License-Identifier: MIT
/// @file What several of cmmcomp-sim's commands share: the move flags in the paper's units and
/// the --machine file (default: the embedded machine, with its implausible values warned of).
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <string>

namespace cmmcomp::tools::sim {

constexpr double kMm = 1e-3;  // mm -> m

/// Move flags in the paper's units (mm, mm/s, mm/s^2), defaults = the paper's baseline.
struct MoveFlags {
  double pv = cmmcomp::paper::kBaseline.pv_mm_s, pa = cmmcomp::paper::kBaseline.pa_mm_s2,
         pd = cmmcomp::paper::kBaseline.pd_mm, av = cmmcomp::paper::kBaseline.av_mm_s,
         aa = cmmcomp::paper::kBaseline.aa_mm_s2, ad = cmmcomp::paper::kBaseline.ad_mm, jerk = 0;

  /// Each flag checked against motion::MoveLimits (in mm): a bad value is a usage error that
  /// names the flag and its range.
  void add_to(CLI::App& app);
  cmmcomp::motion::ProbingMove to_move() const {
    return {pv * kMm, pa * kMm, pd * kMm, av * kMm, aa * kMm, ad * kMm, jerk * kMm};
  }
};

/// A validator that refuses NaN and infinity (CLI::Range lets NaN through: no comparison fails).
CLI::Validator finite_number();

/// The machine of `path` (empty: the embedded one); its implausible values as warnings on stderr.
cmmcomp::dynamics::Machine machine_from(const std::string& path);

}  // namespace cmmcomp::tools::sim
