// SPDX-License-Identifier: MIT
/// @file The twin against the paper over many noise seeds: the calibration verdict
/// (docs/machine-model.md, "Calibration"; docs/study.md).
///
/// dynamics::compare_with_paper judges one noise seed. A requirement is *robust* when it holds
/// for all but one in 50 seeds (`seeds − seeds / 50` of them); paper_calibration runs the seeds
/// seed … seed + seeds − 1 over one set of noiseless simulations and gives one Target per
/// requirement (its name is the requirement's text, as a known-unmet list names it; measured:
/// the seeds it held for; limit: the seeds it must hold for). The first seed's comparison is kept
/// for its tables. Setup-time code: simulates; throws ConfigError for seeds < 1.
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/dynamics/paper_check.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/accuracy.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::study {

struct CalibrationResult {
  std::string machine;  ///< the machine's name
  std::uint64_t seed = 1;
  int seeds = 1;
  int needed = 1;                   ///< seeds a requirement must hold for
  dynamics::PaperComparison first;  ///< the comparison at `seed`
  std::vector<Target> targets;      ///< one per requirement, in the comparison's order
};

CalibrationResult paper_calibration(const dynamics::Machine& machine,
                                    std::uint64_t seed,
                                    int seeds,
                                    const RunOptions& options = {});

}  // namespace cmmcomp::study
