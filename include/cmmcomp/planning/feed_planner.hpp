// SPDX-License-Identifier: MIT
/// @file The feed planner: the fastest probing setting whose point error meets a budget at 95 %,
/// with compensation and without (docs/planner.md).
///
/// The planner chooses PV, PD, AV and AD (the model's inputs) inside the intersection of the
/// machine's limits, the feature's geometry and the model's training ranges; PA and AA stay at
/// the values the model was trained with, because the model cannot say what another
/// acceleration does. It minimises the time per point (MoveProfile: from the start of the
/// positioning move to the touch, with the controller's dwell and smoothing) subject to, at
/// every carriage position Y of the program:
///   compensated:    U95(RAE)              ≤ budget   (the corrected point's error, 95 %)
///   uncompensated:  |RAE| + U95(RAE)      ≤ budget   (the raw touch error, 95 %)
///                   or, with a qualified reference (qualified_reference.hpp), what the
///                   reversal map and the probe qualification leave of it
///   both:           |MAE| + U95(MAE)      ≤ the MAE limit (overtravel and stylus load).
/// Setup-time code (allocates, throws ConfigError): it runs before a program, not in it.
#pragma once

#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/planning/qualified_reference.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace cmmcomp::planning {

/// A closed interval of one setting value, in its unit.
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
};

/// The settings of one probing point (mm, mm/s, mm/s²), as MoveRequest and cmmcomp-vc take them.
struct FeedSetting {
  double pv_mm_s = 0.0;
  double pa_mm_s2 = 0.0;
  double pd_mm = 0.0;
  double av_mm_s = 0.0;
  double aa_mm_s2 = 0.0;
  double ad_mm = 0.0;
};

/// What the planner is asked. Every limit is intersected with the model's training range of the
/// same input; an empty intersection is a ConfigError.
struct PlanProblem {
  double budget_um = 0.0;  ///< bound on |point error| at `coverage` [µm], > 0
  /// The coverage the budget is stated at, in (0, 1): every model's interval must have been
  /// calibrated at it (a model file's `uncertainty.coverage`), else ConfigError. Its U95 is
  /// then that coverage's half-width.
  double coverage = 0.95;
  /// Bound on |MAE| + U95(MAE) [µm], > 0: the approach's largest lag, which the probe's
  /// overtravel and the stylus load allow. Default: generous for a touch-trigger probe.
  double mae_limit_um = 25.0;
  Interval pv_mm_s{0.0, 1e9};     ///< the machine's positioning speeds
  Interval av_mm_s{0.0, 1e9};     ///< the machine's approach speeds
  Interval pd_mm{0.0, 1e9};       ///< positioning distances the feature allows (lo: its minimum)
  Interval ad_mm{0.0, 1e9};       ///< approach distances the feature allows (lo: its minimum)
  Interval pa_mm_s2{0.0, 1e9};    ///< the machine's positioning accelerations (must hold pa_mm_s2)
  Interval aa_mm_s2{0.0, 1e9};    ///< the machine's approach accelerations (must hold aa_mm_s2)
  double pa_mm_s2_model = 200.0;  ///< PA the model was trained at (the paper's)
  double aa_mm_s2_model = 60.0;   ///< AA the model was trained at (the paper's)
  std::vector<double> y_mm{250.0};  ///< carriage positions the setting must hold at
  double z_mm = 0.0;                ///< ram position of the program
  double dwell_s = 0.0;             ///< the controller's settling dwell at the pre-hit point [s]
  double smoothing_s = 0.0;         ///< the controller's command smoothing [s]
  /// Share of each model input's range kept clear at both of its ends, in [0, 0.45). A fitted
  /// model is least sure at the corners of its training box, where the planner's optimum
  /// lands; a model file of version 3 says so itself (its corner gain widens U95 there), one of
  /// version 2 does not, and needs a margin (docs/planner.md, "Edge margin"). 0: the whole box.
  double edge_margin = 0.0;
  /// Points per input of the global grid (>= 2). The local search starts from the fastest
  /// feasible grid points.
  int grid_points = 11;
  /// The local search stops when its step is below this share of each input's range.
  double tolerance = 1e-4;
  /// The uncompensated machine's reversal map and probe qualification (qualified_reference.hpp,
  /// docs/planner.md, "The qualified reference"). Set: an uncompensated setting is judged by
  /// what they leave of its lag, |residual| + √(U95(Y)² + U95(Y_sphere)²), which needs a model
  /// that sees Y (a 5-input model, or a model per Y with one at the sphere's Y). Unset: by the
  /// raw |RAE| + U95. The compensated bound does not change.
  std::optional<QualifiedReference> qualified;
};

/// A model and the carriage position Y it serves: with one model trained at each Y of the
/// program (the paper's Table 2 positions, say), the planner judges a setting at each Y by that
/// Y's model.
struct ModelAtY {
  double y_mm = 0.0;  ///< the carriage position [mm]; a Y of the program
  io::CompensationModelFile model;
};

/// With or without the model's correction.
enum class Mode { kCompensated, kUncompensated };

/// One setting judged: its time and the worst of its constraints over the program's Y.
struct SettingCheck {
  bool feasible = false;
  double time_per_point_s = 0.0;
  /// The 95 % bound of the point error [µm]: U95(RAE) compensated, |RAE| + U95(RAE) without
  /// (qualified: |residual| + the combined U95); the largest over the Y positions.
  double point_bound_um = 0.0;
  double mae_bound_um = 0.0;  ///< |MAE| + U95(MAE), largest over Y [µm]
  double worst_y_mm = 0.0;    ///< where point_bound_um is reached
  double rae_um = 0.0;        ///< the model's RAE at worst_y_mm [µm] (qualified: the residual)
  double u95_rae_um = 0.0;    ///< its U95 [µm] (qualified: √(U95(Y)² + U95(Y_sphere)²))
};

/// The answer for one mode.
struct PlanResult {
  Mode mode = Mode::kCompensated;
  bool found = false;  ///< false: no setting in the domain meets the budget
  FeedSetting setting;
  SettingCheck check;
  long evaluations = 0;  ///< settings judged (each at every Y)
  /// When !found: the smallest point bound any grid setting reached and where, so the user sees
  /// how far the budget is.
  double best_point_bound_um = 0.0;
  FeedSetting best_point_setting;
};

/// Plans settings for one model, or for a model per Y (see the file comment).
class FeedPlanner {
 public:
  /// One model for every Y of the program. Throws ConfigError when the model has no interval
  /// calibration (a format-1 file), when a limit or the budget is not a positive finite value,
  /// when the model's PA/AA lie outside the machine's, or when a limit does not overlap the
  /// model's training range.
  FeedPlanner(const io::CompensationModelFile& model, PlanProblem problem);
  /// A model per Y: at each Y of `problem.y_mm` the setting is judged by the model given for
  /// that Y (to 1e-6 mm), and the search box lies inside every model's training ranges. Throws
  /// ConfigError as above for each model, and when a Y of the program has no model, when two
  /// models are given for one Y, or when a model's Y is not finite.
  FeedPlanner(const std::vector<ModelAtY>& models, PlanProblem problem);

  /// The search box: the problem's limits within the model's ranges.
  Interval pv_mm_s() const { return pv_; }
  Interval pd_mm() const { return pd_; }
  Interval av_mm_s() const { return av_; }
  Interval ad_mm() const { return ad_; }
  const PlanProblem& problem() const { return problem_; }

  /// Time per point of `s` [s], from its planned profiles (dwell and smoothing included).
  double time_per_point_s(const FeedSetting& s) const;
  /// Judges `s` in `mode`.
  SettingCheck check(const FeedSetting& s, Mode mode) const;
  /// The fastest feasible setting: the global grid, then a pattern search from its best points.
  PlanResult plan(Mode mode) const;
  /// The fastest feasible setting of an n^4 grid over the box and nothing else: the reference the
  /// planner is tested against.
  PlanResult brute_force(Mode mode, int points_per_input) const;

  /// Identifier (first 16 hex digits of its checksum) and input count of the model that judges
  /// each Y of the program, in the order of `problem().y_mm`.
  const std::vector<std::string>& model_ids() const { return model_ids_; }
  const std::vector<int>& model_inputs() const { return model_inputs_; }
  /// Whether the planner was given a model per Y.
  bool models_per_y() const { return per_y_; }

 private:
  FeedPlanner(const std::vector<ModelAtY>& models, PlanProblem problem, bool per_y);
  FeedSetting at(double pv, double pd, double av, double ad) const;
  PlanResult grid_search(Mode mode, int n, std::vector<FeedSetting>* best_feasible) const;

  PlanProblem problem_;
  bool per_y_ = false;
  /// One compensator per model (not copyable, hence the pointers), and which one judges each Y
  /// of the program.
  std::vector<std::unique_ptr<compensation::MoveCompensator>> compensators_;
  std::vector<std::size_t> compensator_of_y_;
  std::size_t sphere_compensator_ = 0;  ///< the one that judges the sphere's Y (qualified)
  Interval pv_, pd_, av_, ad_;
  std::vector<std::string> model_ids_;
  std::vector<int> model_inputs_;
};

/// "compensated" / "uncompensated".
const char* to_string(Mode mode);

/// What the planner may take as given instead of the model files' training conditions.
struct GivenConditions {
  std::optional<double> pa_mm_s2, aa_mm_s2;  ///< --trained-pa / --trained-aa
  /// The controller timing of a machine file the user named (--machine); none: not named.
  std::optional<double> dwell_s, smoothing_s;
  std::string machine_label;  ///< how to name it in messages ("the controller of m.toml")
};

/// The PA, AA and controller timing to plan with, and where each came from (for the user).
struct PlanConditions {
  double pa_mm_s2 = 0, aa_mm_s2 = 0, dwell_s = 0, smoothing_s = 0;
  std::string acceleration_source, timing_source;
};

/// Resolves the conditions to plan with (docs/planner.md, "Training conditions"): PA and AA as
/// given, else the highest each model was trained at (every model must contain it); the
/// controller timing of the named machine, else the models' (which must agree within 10 ms).
/// A model's recorded condition that contradicts a given value (PA outside its range, a dwell
/// or smoothing more than 10 ms off) is a ConfigError: the model's errors hold at its
/// conditions only. So is a condition no model records and nothing gives ("model … does not
/// record …: give --trained-pa").
PlanConditions resolve_conditions(const std::vector<const io::TrainingConditions*>& models,
                                  const std::vector<std::string>& model_ids,
                                  const GivenConditions& given);

}  // namespace cmmcomp::planning
