// SPDX-License-Identifier: MIT
/// @file Trains the fixed-size Takagi–Sugeno network (fuzzy/tsk_evaluator.hpp) with Ceres.
///
/// Offline, setup only. `train_fnn` fits a network to samples in raw units and returns it in
/// raw units with a calibrated prediction interval; `train_network<Inputs>` does the same from
/// dataset rows for a schema input set. A pipeline of five stages (docs/training.md, "How the
/// trainer works"): check and normalise; ridge start (prior, λ by k-fold CV); Levenberg–
/// Marquardt refinement (the default) or the paper's gradient descent (the baseline); interval
/// calibration (docs/uncertainty.md).
///
/// Contract: deterministic for a given options.seed, bit-identical on every platform (SplitMix64,
/// one thread). Throws ConfigError for invalid options or data, never for numerical trouble: a
/// failed or non-finite solve is reported in TrainingSummary and the model falls back to the
/// ridge start.
#pragma once

#include <array>
#include <cctype>
#include <cmmcomp/compensation/move_prediction.hpp>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::training {

/// How `train_fnn` fits the network.
enum class FnnMethod : std::uint8_t {
  kLevenbergMarquardt,  ///< ridge initialisation + CV-chosen λ + Ceres LM (the default)
  kGradientDescent,     ///< the paper's plain gradient descent from random parameters (baseline)
};

/// "levenberg-marquardt" or "gradient-descent" (static strings).
const char* to_string(FnnMethod method) noexcept;

/// Which fits give the out-of-fold residuals the interval is calibrated on (stage 5). Both kinds
/// of fold model see (K − 1)/K of the data, so both overstate the served model's error; they
/// overstate it differently per output (docs/uncertainty.md, "Which fold models").
enum class IntervalFolds : std::uint8_t {
  kRidge,     ///< the ridge initialisation at the chosen λ, per fold (milliseconds)
  kAsServed,  ///< each fold trained as the served model (the same LM iterations or GD epochs)
  kNarrower,  ///< LM: per output, the narrower of the two intervals (the default); GD: kAsServed
};

/// "ridge", "as-served" or "narrower" (static strings).
const char* to_string(IntervalFolds folds) noexcept;

/// The IntervalFolds named `text` (to_string's names); ConfigError otherwise.
IntervalFolds parse_interval_folds(const std::string& text);

/// `ModelFile::interval_method` of a model calibrated by train_fnn (stage 5), naming the fold
/// models each output's half-width came from (`TrainingSummary::interval_folds`), in the order
/// of `outputs`, e.g. "split-conformal on design-point-grouped CV residuals (MPE ridge, RPE
/// as-served, …); extrapolation gain from held-out ends".
std::string interval_method(const std::vector<IntervalFolds>& used,
                            const std::vector<std::string>& outputs);

/// interval_method for a network whose outputs are the four error parameters (kErrors' labels).
std::string interval_method(const std::vector<IntervalFolds>& used);

/// Training options. The default method is LM; the GD fields hold the paper's settings for the
/// baseline.
struct FnnTrainingOptions {
  FnnMethod method = FnnMethod::kLevenbergMarquardt;  ///< default LM
  int folds = 5;                                      ///< CV folds, ≥ 2; needs ≥ folds samples
  std::uint64_t seed = 1;                             ///< folds and GD initial parameters
  /// Ridge weight on the consequents [normalised units]; < 0 (default −1): chosen by CV over
  /// `lambda_grid`. 0 = no ridge.
  double lambda = -1.0;
  /// Candidate λ for CV, each finite and ≥ 0; default 1e-6, 1e-5, …, 1e1 (8 values).
  std::vector<double> lambda_grid{1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1};
  /// LM iterations (default 8: with few noisy samples longer runs mostly fit the noise); 0 = keep
  /// the ridge initialisation (no Ceres solve).
  int max_iterations = 8;
  double min_width = 0.02;       ///< lower bound on every width σ [normalised input units] > 0
  double learning_rate = 0.001;  ///< GD step β (paper: 0.001), > 0
  int epochs = 1000;             ///< GD epochs (paper: 1000), ≥ 0
  double goal = 0.05;  ///< GD stops when the mean squared error [normalised] ≤ goal (paper 0.05)
  /// Nominal coverage of the calibrated prediction interval (stage 5); 0 = no calibration.
  double interval_coverage = 0.95;
  /// The fold models of the interval's calibration (stage 5). kAsServed and kNarrower train
  /// `folds` more networks with the served method; with LM and max_iterations = 0 they are the
  /// ridge fits (GD always starts from its random model, so its folds always differ).
  IntervalFolds interval_folds = IntervalFolds::kNarrower;
  /// Optional names of the inputs for messages (size kInputs or empty: "input i").
  std::vector<std::string> input_names;
  /// Called after each LM iteration or GD epoch: (iteration, cost [normalised units]).
  std::function<void(int iteration, double cost)> progress;

  /// True if usable; otherwise false and, if `why` is given, the first problem found.
  bool is_valid(std::string* why) const;
};

/// What happened. Costs are in normalised units (stage 1), RMSEs in the raw
/// output units (µm for the dataset), one entry per output.
struct TrainingSummary {
  FnnMethod method = FnnMethod::kLevenbergMarquardt;
  std::string message;                  ///< termination message (Ceres' for LM)
  bool solution_usable = false;         ///< the solver finished without numerical failure
  bool converged = false;               ///< LM: Ceres converged; GD: goal reached
  int iterations = 0;                   ///< LM iterations or GD epochs run
  double initial_cost = 0;              ///< cost at the start of LM/GD
  double final_cost = 0;                ///< cost at the end
  double lambda = 0;                    ///< ridge weight used
  std::vector<double> lambda_grid;      ///< λ values cross-validated (the grid, or the fixed λ)
  std::vector<double> cv_mse_grid;      ///< CV MSE per grid λ, mean over outputs [normalised]
  std::vector<double> init_train_rmse;  ///< ridge initialisation on the training data
  std::vector<double> train_rmse;       ///< returned model on the training data
  std::vector<double> cv_rmse;          ///< k-fold CV of the ridge initialisation at `lambda`
  /// The prior's shape per output (stage 2), e.g. "first-order", "quadratic(PV×PD)".
  std::vector<std::string> prior;
  std::size_t design_points = 0;     ///< distinct input vectors in the training data
  std::size_t interval_samples = 0;  ///< samples the interval was calibrated on (0: none)
  /// Per output, the fold models its half-width and corner gain came from (kRidge or
  /// kAsServed; empty when not calibrated).
  std::vector<IntervalFolds> interval_folds;
  double wall_seconds = 0;  ///< total time of train_fnn

  /// The returned model can be published: the solve did not fail and every RMSE is finite.
  bool usable() const;
};

/// A trained model and how it was obtained.
template <int kInputs, int kSets, int kOutputs>
struct FnnTrainingResult {
  fuzzy::TskModel<double, kInputs, kSets, kOutputs> model;  ///< raw input and output units
  /// The prediction interval's calibration (stage 5; not available() when not calibrated).
  fuzzy::IntervalCalibration<kOutputs> interval;
  TrainingSummary summary;
};

/// Trains a network from `inputs[n]` (raw units, e.g. mm, mm/s) and `targets[n]` (raw units,
/// e.g. µm) through the stages of the file comment. Setup only. Deterministic for a given
/// options.seed. Throws ConfigError for invalid options, empty data, inputs and targets of
/// different lengths, a non-finite value, fewer samples than options.folds, or an input whose
/// min equals its max (named by options.input_names or its index). Explicitly instantiated for
/// <4,3,4> (schema.hpp's PaperInputs), <5,3,4> (CarriageInputs), <4,3,1> (one output of the
/// paper's network), and the small test sizes <1,3,1>, <1,3,2>, <2,3,1>, <2,3,2>, <2,2,1>.
template <int kInputs, int kSets, int kOutputs>
FnnTrainingResult<kInputs, kSets, kOutputs> train_fnn(
    const std::vector<std::array<double, kInputs>>& inputs,
    const std::vector<std::array<double, kOutputs>>& targets,
    const FnnTrainingOptions& options = {});

/// The split-conformal quantile of stage 5 (docs/uncertainty.md): the ⌈(n + 1)c⌉-th smallest of
/// the n `scores`, the rank clamped to [1, n] (so the largest when (n + 1)c > n: too few samples
/// for the coverage, which then is not guaranteed); 0 when there are no scores. c ∈ (0, 1).
/// Declared here so that the unit tests can check the rule train_fnn uses.
double conformal_quantile(std::vector<double> scores, double c);

/// Dataset rows as training samples: inputs and the four error parameters as targets.
template <int kInputs>
struct Samples {
  std::vector<std::array<double, kInputs>> inputs;       ///< the input set's features, file units
  std::vector<std::array<double, kErrorCount>> targets;  ///< MPE, RPE, MAE, RAE [µm], signed
};

/// The inputs (`Inputs`, a schema InputSet) and targets of every row, in file units.
template <typename Inputs>
Samples<Inputs::kCount> samples(const std::vector<DatasetRow>& rows) {
  Samples<Inputs::kCount> s;
  s.inputs.reserve(rows.size());
  s.targets.reserve(rows.size());
  for (const DatasetRow& r : rows) {
    s.inputs.push_back(Inputs::gather(r));
    s.targets.push_back(gather_errors(r));
  }
  return s;
}

/// The labels of `Inputs` for messages and options.input_names: "PV", "PD", ….
template <typename Inputs>
std::vector<std::string> input_labels() {
  const auto labels = Inputs::labels();
  return {labels.begin(), labels.end()};
}

/// The name of `Inputs` in options and recipes: its labels in lower case, comma separated
/// ("pv,pd,av,ad").
template <typename Inputs>
std::string input_set_name() {
  std::string s;
  for (const char* label : Inputs::labels()) {
    if (!s.empty()) s += ',';
    for (const char* c = label; *c != '\0'; ++c) {
      s += static_cast<char>(std::tolower(static_cast<unsigned char>(*c)));
    }
  }
  return s;
}

/// A network trained on the input set `Inputs` (a schema InputSet): the compensation model with
/// its interval and how it was obtained.
template <typename Inputs>
struct TrainedNetwork {
  compensation::Model<Inputs, double> model;   ///< raw units, the set's inputs in its order
  compensation::IntervalCalibration interval;  ///< not available() when not calibrated
  TrainingSummary summary;
};

/// train_fnn on the inputs `Inputs` gathers from `rows` and their four error parameters, with
/// options.input_names set to the set's labels ("PV", "PD", …). Throws as train_fnn.
template <typename Inputs>
TrainedNetwork<Inputs> train_network(const std::vector<DatasetRow>& rows,
                                     FnnTrainingOptions options = {}) {
  const Samples<Inputs::kCount> s = samples<Inputs>(rows);
  options.input_names = input_labels<Inputs>();
  auto r = train_fnn<Inputs::kCount, compensation::kSetsPerInput, compensation::kModelOutputs>(
      s.inputs, s.targets, options);
  return TrainedNetwork<Inputs>{
      compensation::Model<Inputs, double>(r.model), r.interval, std::move(r.summary)};
}

}  // namespace cmmcomp::training
