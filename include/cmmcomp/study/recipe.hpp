// SPDX-License-Identifier: MIT
/// @file Recipes as data: how an experiment's datasets are simulated and its network fitted
/// (data/recipes/*.toml; docs/study.md, "Recipes").
///
/// A recipe names the network's inputs, the design levels, the machine, the noise, the training
/// parts (designs joined into one dataset, in order), the test design and its seeds, and the fit
/// settings. The shipped models' recipes are data/recipes/default-model.toml and
/// default-y-model.toml; every experiment that measures them reads them, nothing retypes them.
/// Parsing checks every key and value and throws ConfigError "source: key: what is wrong".
/// Setup-time code.
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::study {

/// `format_version` of the recipe files this library reads.
inline constexpr int kRecipeVersion = 1;

/// One simulated design: `design` as doe::design_by_name knows it (l18, l9, l27, full, lhs),
/// `repeats` of every run, `samples` of an lhs design, the noise and lhs seed.
struct DatasetPart {
  std::string design = "l18";
  int repeats = 1;
  int samples = 270;
  std::uint64_t seed = 1;
};

/// How the network is fitted (cmmcomp-train fit's options of the same names).
struct FitSettings {
  std::uint64_t seed = 1;
  std::optional<int> max_iterations;          ///< default: the trainer's
  std::optional<std::string> interval_folds;  ///< ridge, as-served, narrower; default: trainer's
};

/// How an experiment judges the recipe's network (acceptance.hpp, table5_targets).
struct AcceptanceSettings {
  bool reduction = true;         ///< the reduction must reach the paper's Table 5
  double residual_factor = 1.5;  ///< the mean residual at most this × the noise floor
};

struct Recipe {
  std::string name;                    ///< the file's stem ("default-model"), in target names
  std::string source;                  ///< the file, for messages
  std::string description;             ///< one line
  std::string inputs = "pv,pd,av,ad";  ///< the network's inputs, as cmmcomp-train --inputs
  std::string levels;                  ///< doe levels text ("pv=40,70,100;…"); default Table 3's
  std::string machine = "default";     ///< "default" (embedded) or a machine file
  bool noise = true;                   ///< Table 1 noise on every simulated move
  std::string axis = "x";  ///< the axis the twin's moves run along (the model records it)
  std::vector<DatasetPart> training;  ///< joined in this order into one dataset
  DatasetPart test;                   ///< its seed is the first of test_seeds
  std::vector<std::uint64_t> test_seeds;
  FitSettings fit;
  /// (training seed, test seed) pairs: one network per pair, every training part's seed
  /// replaced by the first; empty: one network, tested at every test seed.
  std::vector<std::pair<std::uint64_t, std::uint64_t>> cases;
  AcceptanceSettings acceptance;
};

/// Parses recipe text; `source` names it in messages; a relative machine path is taken relative
/// to `base_dir`.
Recipe parse_recipe(const std::string& text,
                    const std::string& source,
                    const std::string& base_dir);
/// Reads a recipe file (machine paths relative to its folder).
Recipe load_recipe(const std::string& path);

/// The recipe's machine (the embedded default, or its file).
dynamics::Machine recipe_machine(const Recipe& recipe);

/// The rows of `part` simulated on `machine` with the recipe's levels and noise, exactly as
/// cmmcomp-sim dataset writes them (the CSV's 10 significant digits: an experiment sees the
/// numbers a user's file holds). `threads` 0: all cores.
std::vector<DatasetRow> simulate_part(const Recipe& recipe,
                                      const dynamics::Machine& machine,
                                      const DatasetPart& part,
                                      int threads = 0);

/// The training dataset: every training part, joined in order.
std::vector<DatasetRow> training_rows(const Recipe& recipe,
                                      const dynamics::Machine& machine,
                                      int threads = 0);

}  // namespace cmmcomp::study
