// SPDX-License-Identifier: MIT
/// @file A recipe's network, trained as cmmcomp-train fit trains it, as a model file that records
/// its training data's hash and the conditions it was trained at (docs/study.md, "Training").
/// Setup-time code: simulates, trains; throws ConfigError for a recipe whose inputs are not
/// served, Error for a network the trainer could not make usable.
#pragma once

#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/study/recipe.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <optional>
#include <string>
#include <vector>

namespace cmmcomp::study {

/// What a run may change of the recipe's fit settings (the sanitizer builds calibrate on the
/// ridge folds: the fold networks take minutes there).
struct FitOverrides {
  std::optional<std::string> interval_folds;
  std::optional<double> interval_coverage;  ///< the interval's nominal coverage (default 0.95)
};

struct TrainedModel {
  io::CompensationModelFile file;     ///< network, interval, metadata, conditions
  training::TrainingSummary summary;  ///< the trainer's
  std::size_t samples = 0;
};

/// Trains the recipe's network on `rows` (its training data, e.g. training_rows): the recipe's
/// fit settings; `training.data_file_sha256` is the hash of `rows` as io::format_dataset_csv
/// writes them (the hash of the file cmmcomp-study dataset writes); the conditions are the
/// data's PA and AA, the machine's name and controller timing, the recipe's axis, and Table 1's σ
/// as the noise floor when the recipe adds noise.
TrainedModel train_model(const Recipe& recipe,
                         const std::vector<DatasetRow>& rows,
                         const FitOverrides& overrides = {});

}  // namespace cmmcomp::study
