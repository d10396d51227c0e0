// SPDX-License-Identifier: MIT
/// @file A trained network as a model file (docs/model-file.md), and the training report a user
/// reads: what cmmcomp-train fit and cmmcomp-study train both write.
///
/// Contract: model_file() fills every field of the file from the network, its summary and the
/// given provenance and conditions (trained_at: now, UTC); the interval's method and sample
/// count only when the network is calibrated. Setup only.
#pragma once

#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/training/fnn_trainer.hpp>
#include <cstdint>
#include <string>

namespace cmmcomp::training {

/// Where a model came from, for its file's "training" block.
struct Provenance {
  std::string data_sha256;  ///< SHA-256 of the training data's CSV text
  std::uint64_t seed = 1;   ///< FnnTrainingOptions::seed
  std::string tool;         ///< "cmmcomp-train 1.2.3"
};

/// The model file of `network` (see the file comment).
template <typename Inputs>
io::ModelFileOf<Inputs> model_file(const TrainedNetwork<Inputs>& network,
                                   const Provenance& provenance,
                                   const io::TrainingConditions& conditions) {
  const TrainingSummary& s = network.summary;
  io::ModelFileOf<Inputs> file;
  file.model = network.model;
  file.training.data_file_sha256 = provenance.data_sha256;
  file.training.method = to_string(s.method);
  file.training.lambda = s.lambda;
  file.training.cv_rmse = s.cv_rmse;
  file.training.trained_at = io::utc_timestamp_now();
  file.training.seed = provenance.seed;
  file.training.tool_version = provenance.tool;
  file.conditions = conditions;
  file.interval = network.interval;
  if (network.interval.available()) {
    file.interval_method = interval_method(s.interval_folds);
    file.interval_samples = s.interval_samples;
  }
  return file;
}

/// The training as cmmcomp-train fit prints it: the method, samples and time, λ and its origin,
/// the prior per output, and per output the RMSEs and the interval (named U<coverage>).
/// `data_label` names the data; `lambda_chosen`: λ came from cross-validation.
std::string format_training_report(const TrainingSummary& summary,
                                   const compensation::IntervalCalibration& interval,
                                   std::size_t samples,
                                   const std::string& data_label,
                                   bool lambda_chosen,
                                   double coverage);

}  // namespace cmmcomp::training
