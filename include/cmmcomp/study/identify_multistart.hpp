// SPDX-License-Identifier: MIT
/// @file How many minima the identification objective has, measured (docs/machine-model.md,
/// "Cost"; docs/study.md).
///
/// training::identify_machine runs from N starts: start 0 is the start machine itself, start i
/// scales every free parameter by 2^u with u uniform in [−spread, spread] (SplitMix64 seeded
/// with seed·1000 + i). Each fitted machine is then judged by paper_calibration over
/// `calibration_seeds` noise seeds from `calibration_seed`. A start whose scaled value leaves
/// the plausible range, or whose fit fails, is a row with its reason, not an abort.
/// It changes nothing in the project. Setup-time code: simulates, fits (minutes per start).
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cmmcomp/training/machine_identification.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::study {

struct MultistartPlan {
  int starts = 12;
  double spread = 0.7;
  std::uint64_t seed = 7;
  std::uint64_t calibration_seed = 101;
  int calibration_seeds = 50;
};

struct MultistartRow {
  int start = 0;
  std::string failure;  ///< why no fit came out of this start; empty when it did
  double initial_cost = 0, final_cost = 0;
  double seconds = 0;                               ///< wall time of the fit
  std::vector<double> start_values, fitted_values;  ///< of the free parameters, SI
  std::vector<int> at_bound;
  int requirements = 0, held = 0;  ///< calibration requirements, and those held robustly
};

struct MultistartResult {
  std::vector<std::string> free_parameters;
  std::vector<MultistartRow> rows;
};

/// The paper's identification targets and weights, as scripts/identify-default-machine.sh fits
/// the default machine: Tables 1 and 2 as measured moves (magnitudes, σ 4 % of each value),
/// Table 4's weights (σ 5 points) and Table 5's grid means (σ 5 %), read from `paper_dir`
/// (data/paper). The options free nothing yet and fix nothing (the controller timing is fitted
/// too, as the paper's tables cannot measure it).
struct PaperIdentification {
  training::IdentificationTargets targets;
  training::IdentificationOptions options;
};
PaperIdentification paper_identification(const std::string& paper_dir);

/// Runs the fits (file comment) from `start` with `targets` and `options` (its free parameters
/// are the ones scaled; its progress callback is left to the caller).
MultistartResult identify_multistart(const dynamics::Machine& start,
                                     const training::IdentificationTargets& targets,
                                     const training::IdentificationOptions& options,
                                     const MultistartPlan& plan,
                                     const RunOptions& run = {});

}  // namespace cmmcomp::study
