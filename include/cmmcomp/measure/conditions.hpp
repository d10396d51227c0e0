// SPDX-License-Identifier: MIT
/// @file The training conditions a model records (docs/model-file.md, "Conditions"), from what
/// the user has: the dataset, the campaign summaries of cmmcomp-measure extract, the machine
/// file a twin dataset was simulated with, and what they state by hand.
///
/// Contract: PA and AA come from the data unless given; the controller timing, the axis and the
/// noise floor from the campaigns; a machine file adds its name and, where no campaign gives
/// it, its timing; a stated axis or noise floor sets theirs. Two sources that disagree (timing
/// by more than 10 ms, the axis) are a ConfigError naming both values and the fix.
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/schema.hpp>
#include <optional>
#include <string>
#include <vector>

namespace cmmcomp::measure {

/// Where a model's conditions come from besides the dataset.
struct ConditionSources {
  std::vector<CampaignSummary> campaigns;
  std::optional<dynamics::Machine> machine;  ///< the twin the data was simulated with
  std::string machine_label;                 ///< how the user named it, for messages
  std::string axis;                          ///< stated axis; empty: the campaigns'
  std::vector<double> noise_floor;           ///< stated, one per parameter; empty: the campaigns'
  std::optional<io::ConditionRange> pa_mm_s2, aa_mm_s2;  ///< stated; none: the data's
};

/// The conditions of a model trained on `rows` (see the file comment).
io::TrainingConditions training_conditions(const std::vector<DatasetRow>& rows,
                                           const ConditionSources& sources);

/// The conditions as one line for the user, "unknown" where the model will not know them.
std::string describe_conditions(const io::TrainingConditions& conditions);

/// "LO" or "LO:HI" [mm/s²], 0 < LO <= HI. ConfigError naming `option`.
io::ConditionRange parse_condition_range(const std::string& text, const std::string& option);
/// "table1" (the paper's Table 1 σ, the twin's noise) or MPE,RPE,MAE,RAE [µm], each >= 0.
/// ConfigError naming --noise-floor.
std::vector<double> parse_noise_floor(const std::string& text);

}  // namespace cmmcomp::measure
