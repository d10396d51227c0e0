// SPDX-License-Identifier: MIT
/// @file Trains the fixed-size Takagi–Sugeno network (fuzzy/tsk_evaluator.hpp) with Ceres.
///
/// Offline, setup only. What `train_fnn` does, in order (docs/fuzzy-network.md for the network):
///  1. **Checks** the options and data (ConfigError: invalid options, no samples, sizes that
///     differ, a NaN or inf value, fewer samples than folds, an input with min == max).
///  2. **Normalises.** Input ranges of the model = the training data's min/max per input (so the
///     data maps onto [0, 1]); targets are scaled per output to z = (y − mean)/std (population
///     std; 1 if an output is constant), so outputs of different size weigh equally. All costs,
///     λ and the GD goal are in these normalised units; the returned model is in raw units (the
///     consequents are scaled back: p0 ← std·p0 + mean, p_k ← std·p_k, exact because Σᾱ = 1).
///  3. **Initialises** the premise deterministically: the centres of input i evenly over [0, 1]
///     (0, 0.5, 1 for 3 sets; 0.5 for one set), every width σ = the centre spacing (a neighbour's
///     centre gets μ = e⁻¹; σ = 1 for one set). The consequents are then linear in the output:
///     they come from a ridge least-squares solve with the premise fixed that shrinks every
///     rule towards a **prior** rather than towards zero: p = p₀ + Φᵀ(ΦΦᵀ + λI)⁻¹(z − Φp₀)
///     (Eigen, dual form; Φ the N × kRules·(kInputs+1) matrix of ᾱ_j·[1, x]). The prior p₀ is,
///     per output, the global first-order fit g (least squares of z on [1, x]) in every rule,
///     or — when every input of the data sits on exactly three levels, a designed experiment —
///     the shape chosen by leave-one-design-point-out CV among g and tensor quadratics over one
///     input or over the pair with the two largest main effects (heredity: the design aliases
///     the other pairs with it), with or without first-order terms in the others, put into each
///     rule as the shape's tangent plane at the rule's centre (src/training/fnn_prior.hpp).
///     Why: 54 samples of 18 distinct moves cannot pin down 405 consequents per output; between
///     the training moves a ridge towards zero pulls the prediction towards the mean, a ridge
///     towards g falls back on the best first-order model (Σᾱ = 1, so rules all equal to g
///     give exactly g·[1, x]). On the default twin g halved the test residual of MPE and RPE
///     against a ridge towards zero; on the paper's L18 the quadratic through the nine
///     (PV, PD) cell means, which is what an ANOVA reads off the design, raised RPE's test
///     reduction from 87–88 % to 91.1–92.7 % (docs/training.md, "The prior"). This alone is
///     already a good model (`max_iterations = 0` stops here).
///  4. **Chooses λ** (options.lambda < 0) by k-fold cross-validation over `lambda_grid`: folds
///     from a seeded shuffle; inside CV the premise stays at the initialisation and only the
///     ridge consequents and g are refitted per fold (one eigen-decomposition of the fold's N×N
///     Gram matrix serves every λ, so CV costs milliseconds). The λ with the lowest CV mean squared
///     error, averaged over the outputs in normalised units, wins (ties: the larger λ). CV RMSE
///     per output at the λ used is reported in raw units; it scores the ridge initialisation,
///     not the LM-refined model. A fixed λ ≥ 0 skips the choice but is still cross-validated.
///  5. **Refines** with Levenberg–Marquardt on all data at that λ (method kLevenbergMarquardt),
///     only when the data hold more design points (distinct input vectors) than the premise
///     has centres and widths (2·kInputs·kSets = 24 for the paper's network); with fewer the
///     data cannot place the premise, and LM bent the network between the 18 moves of the L18
///     (RPE reduction −3 to −5 points), so the ridge initialisation is kept and the summary
///     says why. The LM cost:
///     ½Σ_n,o (ŷ_o(x_n) − z_no)² + ½λ Σ (p − p₀)², p every consequent (normalised units). The
///     residual of sample n and output o is `FnnSampleResidual` below, which calls
///     `TskEvaluator<T, kInputs, kSets, 1>::forward` — the RT code, here differentiated with
///     ceres::Jet through ceres::DynamicAutoDiffCostFunction (stride kFnnJetStride; exact
///     Jacobians). Output o of a kOutputs network is exactly the single-output network made of
///     the shared premise and consequent block o, so that is what each residual evaluates.
///     Parameter blocks: one premise block (centres, widths: 2·kInputs·kSets values) shared by
///     all outputs, and one block per rule and output (kInputs + 1 consequents), so that the
///     ridge residuals √λ·(p − p₀) have a block-diagonal Jacobian. Widths are kept ≥ `min_width`
///     with SetParameterLowerBound (bounds, not a log parametrisation: the evaluator's σ is used as
///     is). Linear solver: dense normal Cholesky up to 1000 parameters, sparse normal Cholesky
///     above (the premise couples the outputs only weakly); one thread, so results do not
///     depend on the machine's core count.
///  6. Or, with method kGradientDescent, **the paper's training** as a baseline: random initial
///     parameters (seeded; centres U(0, 1), widths U(0.5, 1.5)·spacing, consequents
///     U(−0.5, 0.5)), then full-batch plain gradient descent on E = ½Σ(z − ŷ)² (+ ½λΣp² when
///     options.lambda > 0; the paper has no ridge) with the gradient from the same Jet code
///     (ceres::Problem::Evaluate), learning rate 0.001, at most 1000 epochs, stopping when the
///     mean squared error over samples and outputs (normalised units) is ≤ goal 0.05; widths
///     are projected onto ≥ min_width after each step. CV is still run and reported (it scores
///     the ridge initialisation of step 3, as for LM, so both methods report the same figure).
///  7. **Calibrates the prediction interval** (options.interval_coverage > 0, default 0.95;
///     docs/uncertainty.md): the split-conformal quantile of cross-validated residuals, the folds
///     made of whole design points (with LM on ≤ 24 design points, one design point per fold,
///     so that no fold empties a cell of the design), and the interval's growth outside the
///     training box from fits with one end of one input held out. The fold models are ridge
///     fits (milliseconds) and,
///     with options.interval_folds ≠ kRidge, also networks trained as the served one (one more
///     LM solve, or GD run, per fold); by default each output takes the narrower interval with
///     LM, and the folds trained as served with GD, whose random start makes the ridge fits no
///     estimate of the served model's error.
///
/// Randomness: SplitMix64 (Steele, Lea, Flood 2014; the constants of Vigna's reference code)
/// seeded with options.seed, with uniform doubles from the top 53 bits and bounded integers by
/// rejection — no std:: distributions, so results are bit-identical on every platform. The fold
/// assignment is a Fisher–Yates shuffle of the sample indices, sample at shuffled position k in
/// fold k mod folds.
///
/// Errors: ConfigError for invalid options or data (never for numerical trouble: a failed or
/// non-finite solve is reported in TrainingSummary, and the model falls back to the ridge
/// initialisation when the refined parameters are not finite).
///
/// Speed (release preset, shared 2-core machine, `cmmcomp-train fit` wall time): the paper's
/// inputs with 4 outputs (1644 parameters) on the shipped model's 324 samples (L18 × 3 + LHS
/// 270) 9.4 s with `interval_folds = kRidge`, 49.8 s with the default kNarrower (five more LM
/// solves, one per calibration fold; 2026-12-05). On L18 × 3 (54 samples, 18 design points, no
/// LM) 0.05 s and 0.08 s (2026-12-06). CV and the prior's choice take < 10 ms; the Jet
/// Jacobian of each LM iteration dominates (bench_training).
#pragma once

#include <array>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cmmcomp::training {

/// How `train_fnn` fits the network.
enum class FnnMethod : std::uint8_t {
  kLevenbergMarquardt,  ///< ridge initialisation + CV-chosen λ + Ceres LM (the default)
  kGradientDescent,     ///< the paper's plain gradient descent from random parameters (baseline)
};

/// "levenberg-marquardt" or "gradient-descent" (static strings).
const char* to_string(FnnMethod method) noexcept;

/// Which fits give the out-of-fold residuals the interval is calibrated on (step 7). Both kinds
/// of fold model see (K − 1)/K of the data, so both overstate the served model's error; they
/// overstate it differently per output (docs/uncertainty.md, "Which fold models").
enum class IntervalFolds : std::uint8_t {
  kRidge,     ///< the ridge initialisation at the chosen λ, per fold (milliseconds)
  kAsServed,  ///< each fold trained as the served model (the same LM iterations or GD epochs)
  kNarrower,  ///< LM: per output, the narrower of the two intervals (the default); GD: kAsServed
};

/// "ridge", "as-served" or "narrower" (static strings).
const char* to_string(IntervalFolds folds) noexcept;

/// `ModelFile::interval_method` of a model calibrated by train_fnn (step 7), naming the fold
/// models each output's half-width came from (`TrainingSummary::interval_folds`), in the order
/// of `outputs`, e.g. "split-conformal on design-point-grouped CV residuals (MPE ridge, RPE
/// as-served, …); extrapolation gain from held-out ends".
std::string interval_method(const std::vector<IntervalFolds>& used,
                            const std::vector<std::string>& outputs);

/// Jet stride of the DynamicAutoDiffCostFunction (derivatives computed per pass).
inline constexpr int kFnnJetStride = 64;

/// Training options. Defaults reproduce the paper's settings for the GD baseline.
struct FnnTrainingOptions {
  FnnMethod method = FnnMethod::kLevenbergMarquardt;  ///< default LM
  int folds = 5;                                      ///< CV folds, ≥ 2; needs ≥ folds samples
  std::uint64_t seed = 1;                             ///< folds and GD initial parameters
  /// Ridge weight on the consequents [normalised units]; < 0 (default −1): chosen by CV over
  /// `lambda_grid`. 0 = no ridge.
  double lambda = -1.0;
  /// Candidate λ for CV, each finite and ≥ 0; default 1e-6, 1e-5, …, 1e1 (8 values).
  std::vector<double> lambda_grid{1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 1e-1, 1e0, 1e1};
  /// LM iterations (default 8: each costs ~50 ms for a PaperNetwork, and with 54 noisy samples
  /// longer runs mostly fit the noise); 0 = keep the ridge initialisation (no Ceres solve).
  int max_iterations = 8;
  double min_width = 0.02;       ///< lower bound on every width σ [normalised input units] > 0
  double learning_rate = 0.001;  ///< GD step β (paper: 0.001), > 0
  int epochs = 1000;             ///< GD epochs (paper: 1000), ≥ 0
  double goal = 0.05;  ///< GD stops when the mean squared error [normalised] ≤ goal (paper 0.05)
  /// Nominal coverage of the calibrated prediction interval (step 7); 0 = no calibration.
  double interval_coverage = 0.95;
  /// The fold models of the interval's calibration (step 7). kAsServed and kNarrower train
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

/// What happened. Costs are in normalised units (step 2 of the file comment), RMSEs in the raw
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
  /// The prior's shape per output (step 3), e.g. "first-order", "quadratic(PV×PD)".
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
  /// The prediction interval's calibration (step 7; not available() when not calibrated).
  fuzzy::IntervalCalibration<kOutputs> interval;
  TrainingSummary summary;
};

/// Trains a network from `inputs[n]` (raw units, e.g. mm, mm/s) and `targets[n]` (raw units,
/// e.g. µm) as described in the file comment. Setup only. Deterministic for a given
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

/// The split-conformal quantile of step 7 (docs/uncertainty.md): the ⌈(n + 1)c⌉-th smallest of
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

/// The residual of one sample for one output, ŷ(x) − z, evaluated by the RT forward pass.
/// Parameter blocks (DynamicAutoDiffCostFunction): block 0 = the premise (centres then widths,
/// 2·kInputs·kSets values, layout as tsk_params.hpp), blocks 1…kRules = the kInputs + 1
/// consequents of rule j − 1 for this output. One residual.
template <int kInputs, int kSets>
struct FnnSampleResidual {
  using Layout = fuzzy::TskLayout<kInputs, kSets, 1>;
  static constexpr int kPremiseSize = Layout::kConsequentsOffset;  ///< 2·kInputs·kSets
  static constexpr int kRules = Layout::kRules;
  static constexpr int kTerms = Layout::kTerms;

  std::array<double, kInputs> input{};  ///< normalised inputs of the sample
  double target = 0;                    ///< normalised target of this output

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    using Net = fuzzy::TskEvaluator<T, kInputs, kSets, 1>;
    // The flat layout forward() reads; heap (std::vector) because it holds 429 Jets for the
    // paper's network, reused per thread to keep allocation out of the Jacobian loop.
    thread_local std::vector<T> params;
    params.resize(static_cast<std::size_t>(Layout::kParamCount));
    for (int k = 0; k < kPremiseSize; ++k) params[static_cast<std::size_t>(k)] = blocks[0][k];
    for (int j = 0; j < kRules; ++j) {
      for (int t = 0; t < kTerms; ++t) {
        params[static_cast<std::size_t>(Layout::consequent_index(0, j, t))] = blocks[1 + j][t];
      }
    }
    typename Net::Input x;
    for (int i = 0; i < kInputs; ++i)
      x[static_cast<std::size_t>(i)] = T(input[static_cast<std::size_t>(i)]);
    typename Net::Output y;
    Net::forward(params.data(), x, y);  // the RT code
    residual[0] = y[0] - T(target);
    return true;
  }
};

}  // namespace cmmcomp::training
