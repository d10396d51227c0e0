// SPDX-License-Identifier: MIT
/// @file Fits a machine file's physical parameters to measured moves (and ANOVA shares) with Ceres.
///
/// Offline; the only Ceres user besides the fuzzy-network trainer. Each free parameter is fitted
/// in log space inside its physical bounds (machine_parameter_table()), so it stays positive.
/// The residuals are (simulated − measured) / σ for every measured move and parameter, plus,
/// optionally, (model share − target share) / σ_share for the ANOVA weights of an L18 experiment
/// (how the default machine is identified against the paper's Table 4).
#pragma once

#include <array>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/io/dataset_csv.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <functional>
#include <string>
#include <vector>

namespace cmmcomp::training {

/// Target ANOVA weights [%] of an L18 × repeats experiment, per parameter (MPE, RPE, MAE, RAE)
/// and source (PV, PD, AV, AD, error). The model's shares are computed from its noiseless run
/// values plus the expected contribution of the measurement noise: each factor gets
/// dof·σ²/repeats, the error row (runs − 1 − Σ dof)·σ²/repeats.
struct AnovaTargets {
  bool enabled = false;
  std::array<std::array<double, 5>, 4> weight_pct{};  ///< [parameter][PV, PD, AV, AD, error]
  int repeats = 3;                                    ///< repeats per run in the experiment
  dynamics::FixedSettings fixed{};                    ///< PA, AA, Y of the experiment
  double sigma_pct = 3.0;                             ///< share residual scale [percentage points]
};

/// Target mean |value| [µm] per parameter (MPE, |RPE|, MAE, |RAE|) over a full-factorial grid of
/// the paper's Table 3 levels: the paper's Table 5 "mean before". The model's means are
/// noiseless (the noise's effect on a mean |value| is far below the tolerance).
struct GridMeanTargets {
  bool enabled = false;
  std::array<double, 4> mean_um{};  ///< [MPE, RPE, MAE, RAE]
  dynamics::FixedSettings fixed{};  ///< PA, AA, Y of the grid
  double relative_sigma = 0.05;     ///< residual scale, a fraction of each target
};

/// What to fit.
struct IdentificationTargets {
  std::vector<DatasetRow> moves;  ///< measured moves: settings and their four errors [µm]
  /// Compare |RPE| and |RAE| (for data that reports magnitudes, like the paper's tables).
  bool compare_magnitudes = false;
  AnovaTargets anova{};
  GridMeanTargets grid_mean{};
};

/// How to fit.
struct IdentificationOptions {
  /// Keys ("section.key") of the parameters to fit; empty = every identifiable one that is not
  /// in `fixed_parameters`.
  std::vector<std::string> free_parameters;
  /// Keys never fitted: what the recordings fix. By default the controller timing, which
  /// `cmmcomp-measure extract` measures from the scale traces (docs/measurement.md); naming one
  /// in `free_parameters` too is a ConfigError.
  std::vector<std::string> fixed_parameters = {"controller.dwell_s", "controller.smoothing_s"};
  /// Residual scale per parameter [µm]; defaults: the paper's Table 1 standard deviations.
  std::array<double, 4> sigma_um = paper::kTable1Std;
  /// When > 0, the measured moves' residual scale is this fraction of each measured value
  /// instead of `sigma_um` (to weigh targets by a relative tolerance, as the paper's tables are
  /// checked). `sigma_um` still sets the noise share of the ANOVA targets.
  double relative_move_sigma = 0.0;
  int max_iterations = 50;  ///< Levenberg–Marquardt iterations
  int threads = 0;          ///< simulation threads (0 = all cores)
  double log_step = 1e-2;   ///< finite-difference step in log(parameter)
  /// Simulate with CVODE (rtol 1e-6, 1e-10 m) instead of the exponential integrator (1 ms steps):
  /// the path the shipped default machine was identified on (docs/machine-model.md, "Cost").
  bool cvode = false;
  /// Called after each iteration: (iteration, cost).
  std::function<void(int, double)> progress;

  bool is_valid(std::string* why) const;
};

/// One residual of the fit, for the report.
struct IdentificationResidual {
  std::string name;       ///< e.g. "move 2 (Y 500 mm) MAE" or "ANOVA RAE AD weight"
  double target = 0;      ///< measured value [µm] or share [%]
  double fitted = 0;      ///< model value at the end
  double normalized = 0;  ///< (fitted − target) / σ
};

/// The outcome.
struct IdentificationReport {
  dynamics::Machine fitted;  ///< the start machine with the free parameters fitted
  std::vector<std::string> free_parameters;
  std::vector<double> start_values, fitted_values;  ///< of the free parameters, SI
  /// Per free parameter: −1 at its plausible minimum, +1 at its maximum (within 1 %), else 0.
  /// A parameter at a bound means the data want a value outside the plausible range: a
  /// mechanism is missing from the model, or a fixed key is wrong.
  std::vector<int> at_bound;
  std::vector<double> bound_values;  ///< the bound each parameter sits at (0 when none)
  /// Per free parameter: its fitted value's 1σ uncertainty as a fraction of the value, from the
  /// Jacobian at the fit ((JᵀJ)⁻¹ of the normalised residuals, times residual_scale²); infinite
  /// when the data do not determine it (a parameter of a near-singular direction), or when the
  /// Jacobian could not be simulated. Meaningful only if the model can describe the data.
  std::vector<double> relative_sigma;
  /// √(max(1, reduced χ²)): how much wider than their σ the residuals spread at the fit (1: as
  /// the σ say); the uncertainties are scaled by it, never narrowed.
  double residual_scale = 1.0;
  double initial_cost = 0, final_cost = 0;  ///< ½ Σ normalized²
  int iterations = 0;
  std::string termination;  ///< Ceres' message
  bool usable = false;      ///< Ceres converged or stopped at the iteration limit without error
  std::vector<IdentificationResidual> residuals;
};

/// Runs the fit. Throws ConfigError for invalid options, an unknown or non-identifiable parameter
/// name, or no targets; Error when a simulation fails at the start point.
IdentificationReport identify_machine(const dynamics::Machine& start,
                                      const IdentificationTargets& targets,
                                      const IdentificationOptions& options);

/// Reads ANOVA targets in the layout of the paper's Table 4 CSV
/// (`factor,mpe_weight_pct,mpe_f,rpe_weight_pct,rpe_f,mae_weight_pct,mae_f,rae_weight_pct,rae_f`,
/// rows PV, PD, AV, AD and error in any order; F columns ignored). Throws ConfigError naming the
/// file and line.
AnovaTargets read_anova_targets(const std::string& path);

/// Reads grid-mean targets in the layout of the paper's Table 5 CSV
/// (`parameter,mean_before_um,...`, rows MPE, MAE, RPE, RAE in any order; other columns ignored).
/// Throws ConfigError naming the file and line.
GridMeanTargets read_grid_mean_targets(const std::string& path);

/// The identification as cmmcomp-sim identify prints it: the cost, each free parameter's start
/// and fitted value (marked at a plausible bound), and each residual against its target.
/// `machine_name` names the start machine, `data_label` the measured moves.
std::string format_identification_report(const IdentificationReport& report,
                                         const std::string& machine_name,
                                         const std::string& data_label);
/// The fit's warnings: the residuals spreading more than twice their σ (residual_scale > 2),
/// and one per free parameter that ended at a plausible bound, naming the bound, what it means
/// and what to check (empty: a fit the model describes to its noise, inside the ranges).
std::vector<std::string> bound_warnings(const IdentificationReport& report);

}  // namespace cmmcomp::training
