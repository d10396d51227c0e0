// SPDX-License-Identifier: MIT
/// @file Experiments on the network's accuracy over the digital twin (docs/study.md):
///  - fit_and_test: a recipe's network trained on its training design and tested on its test
///    design at each test seed (or on each (training seed, test seed) case), with Table 5 and
///    the interval's coverage per test;
///  - cell_interpolant: what a design's (PV, PD) cell means alone predict of RPE (the tensor
///    quadratic through the nine cell means of a three-level design), tested the same way.
/// Both return their numbers and the acceptance targets built from them (acceptance.hpp).
/// Setup-time code: allocates, simulates, trains; throws ConfigError or Error.
#pragma once

#include <array>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cmmcomp::study {

/// One test of a trained network.
struct AccuracyTest {
  std::string label;  ///< "RECIPE train T test S"
  std::uint64_t train_seed = 0, test_seed = 0;
  std::size_t train_samples = 0;
  training::TestSetEvaluation evaluation;
};

/// What fit_and_test measured, with its targets (named "LABEL: mpe_reduction", …).
struct AccuracyResult {
  std::string recipe;
  std::vector<AccuracyTest> tests;
  std::vector<Target> targets;
};

/// One test of a model file on `rows`: training::evaluate_test_set over whichever input set the
/// file has (what `cmmcomp-train eval` computes).
training::TestSetEvaluation evaluate_model_file(const io::CompensationModelFile& file,
                                                const std::vector<DatasetRow>& rows,
                                                const std::string& label);

/// Options of an experiment run.
struct RunOptions {
  int threads = 0;                                   ///< simulation threads (0: all cores)
  std::function<void(const std::string&)> progress;  ///< a line per step, or nothing
};

/// The recipe's network on its test design (file comment). With `recipe.cases`, one network per
/// case (training seeds replaced by its first, tested at its second); else one network tested at
/// every test seed. Targets: table5_targets with the recipe's acceptance settings.
AccuracyResult fit_and_test(const Recipe& recipe, const RunOptions& options = {});

/// The cell interpolant's RPE on one (training, test) pair of a recipe whose training is one
/// three-level design.
struct CellInterpolantTest {
  std::string label;
  double mean_before_um = 0, mean_after_um = 0, reduction_pct = 0;
};
struct CellInterpolantResult {
  std::string recipe;
  std::vector<CellInterpolantTest> tests;
  std::vector<Target> targets;  ///< "LABEL: rpe_reduction" (≥ paper) and "LABEL: rpe_residual"
};

/// For every case (or test seed) of `recipe`: the tensor quadratic in PV and PD through the nine
/// cell means of the training data's RPE, tested on the test design. ConfigError when the
/// training data do not have three PV and three PD levels with every cell filled.
CellInterpolantResult cell_interpolant(const Recipe& recipe, const RunOptions& options = {});

}  // namespace cmmcomp::study
