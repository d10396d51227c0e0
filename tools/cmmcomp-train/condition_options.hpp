// SPDX-License-Identifier: MIT
/// @file The options fit and conditions share: where a model's training conditions come from
/// (docs/model-file.md, "Conditions").
#pragma once

#include <CLI/CLI.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <string>
#include <vector>

namespace cmmcomp::tools::train {

/// Where a model's training conditions come from (docs/model-file.md, "Conditions").
struct ConditionOptions {
  std::vector<std::string> campaigns;
  std::string machine, axis, noise_floor;
  std::string pa, aa;  ///< LO[:HI] [mm/s²]; empty: from the data
};

/// Adds the options of ConditionOptions to `cmd`.
void add_condition_options(CLI::App* cmd, ConditionOptions& c);

/// The conditions the model records (measure/conditions.hpp) from the options.
cmmcomp::io::TrainingConditions fit_conditions(const ConditionOptions& cmd,
                                               const std::vector<cmmcomp::DatasetRow>& rows);

}  // namespace cmmcomp::tools::train
