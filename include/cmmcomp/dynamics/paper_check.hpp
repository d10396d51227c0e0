// SPDX-License-Identifier: MIT
/// @file Compares a machine with the paper's Tables 1, 2 and 4 (the default machine's contract).
#pragma once

#include <array>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/io/dataset_anova.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::dynamics {

/// One requirement and whether the machine meets it.
struct PaperCheck {
  std::string requirement;  ///< e.g. "baseline MPE within ±20 % of 13.622 µm"
  bool passed = false;
  std::string measured;  ///< what was found, e.g. "13.41 µm"
};

/// The machine next to the paper.
struct PaperComparison {
  std::array<errors::DynamicErrors, 3> by_y{};  ///< noiseless baseline at Y = 0, 250, 500 mm [µm]
  io::DatasetAnova anova;                       ///< L18 × 3 with Table 1 noise
  std::vector<PaperCheck> checks;               ///< Table 1, Table 2 and Table 4 requirements
  bool all_passed() const;
};

/// Simulates the baseline at the three carriage positions and the L18 × 3 experiment (noise seed
/// `seed`) and checks: baseline MPE, |RPE|, MAE, |RAE| within ±20 % of Table 1; at Y = 500 each
/// ≥ 1.4× its Y = 250 value and at Y = 0 within ±30 % of Table 2; in the ANOVA, PV the largest
/// factor for MPE and RPE, AV for MAE and RAE, PD in the top two for RPE, AD in the top two for
/// RAE, and the error row below 25 % for every parameter.
PaperComparison compare_with_paper(const Machine& machine, std::uint64_t seed, int threads = 0);

/// Side-by-side tables (model vs paper) and the list of checks.
std::string format_paper_comparison(const PaperComparison& c);

}  // namespace cmmcomp::dynamics
