// SPDX-License-Identifier: MIT
/// @file cmmcomp-plan's question as one library call (docs/planner.md): the fastest
/// compensated and the fastest uncompensated setting at one point-error budget, and the report
/// a user reads (a Markdown table, or JSON), with the option texts the tool accepts.
///
/// Contract: plan_feeds() resolves the budget (given, or share × MPE_E(L)) and the training
/// conditions (resolve_conditions), builds the FeedPlanner and runs both modes, and the brute
/// force check when asked. It throws ConfigError for an invalid request, as the planner does.
/// The formatters write what cmmcomp-plan prints; the JSON's fields are docs/planner.md's.
/// Setup-time code.
#pragma once

#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/motion/controller_capabilities.hpp>
#include <cmmcomp/planning/feed_planner.hpp>
#include <string>
#include <vector>

namespace cmmcomp::planning {

/// The point-error budget: `budget_um` when > 0, else share × MPE_E(length), MPE_E = A + L/K.
struct BudgetSpec {
  double budget_um = 0.0;  ///< > 0: given [µm]
  double share = 0.5;      ///< of MPE_E(L) one point may use, in (0, 1]
  double length_mm = 20.0;
  double mpe_a_um = 1.9;  ///< A of MPE_E [µm]
  double mpe_k = 300.0;   ///< K of MPE_E (L/K in µm for L in mm), > 0
};

/// What the user asks. `problem` carries the search box, the Y, the coverage, the grid, the
/// edge margin, the MAE limit and the qualified reference; plan_feeds fills its budget, its
/// PA and AA and the controller timing.
struct PlanRequest {
  PlanProblem problem;
  BudgetSpec budget;
  GivenConditions given;
  /// False: the Y were not given, and with a model per Y they are the models' Y.
  bool y_given = true;
  int brute_force_points = 0;  ///< > 0: also an exhaustive N⁴ grid per mode, as a check
};

/// The answer and everything the report states.
struct PlanReport {
  PlanProblem problem;        ///< as planned (budget, conditions and Y resolved)
  std::string budget_source;  ///< "given" or how it follows from MPE_E
  PlanConditions conditions;
  std::vector<std::string> model_ids;
  std::vector<int> model_inputs;
  bool models_per_y = false;
  Interval pv_mm_s, pd_mm, av_mm_s, ad_mm;  ///< the search box within the models' ranges
  /// Every model's interval has a corner gain (false: its U95 may be too narrow in the corners).
  bool corner_aware = true;
  PlanResult compensated, uncompensated;
  int brute_force_points = 0;
  std::vector<PlanResult> brute_force;  ///< compensated, uncompensated (when asked)

  /// Uncompensated over compensated time per point; 0 unless both were found.
  double speedup() const;
};

/// Plans with one model for every Y (`per_y` empty) or a model per Y.
PlanReport plan_feeds(const io::CompensationModelFile& model,
                      const std::vector<ModelAtY>& per_y,
                      PlanRequest request);

/// The human report: the models, the budget, the search box, the table of both settings and
/// the verdict.
std::string format_plan_table(const PlanReport& report);
/// The report as JSON text (docs/planner.md, "JSON").
std::string format_plan_json(const PlanReport& report);
/// The settings found as cmmcomp-vc --fast/--slow values: "compensated=pv=…,…" and
/// "uncompensated=…" lines (a line only for a setting found).
std::string format_vc_settings(const PlanReport& report);

/// Narrows the machine limits of `problem` (PV, PA, AV, AA, and AD with the feature's) to what
/// the machine's controller accepts (docs/machine-file.md, "Capabilities"), so that no planned
/// setting is one the controller refuses. ConfigError naming the setting, both ranges and
/// `machine` when an intersection is empty.
void restrict_to_capabilities(PlanProblem& problem,
                              const motion::ControllerCapabilities& capabilities,
                              const std::string& machine);

/// Option texts. Each throws ConfigError naming `option`.
/// "LO:HI" with 0 <= LO <= HI.
Interval parse_interval(const std::string& text, const std::string& option);
/// "a,b,c" → numbers.
std::vector<double> parse_number_list(const std::string& text, const std::string& option);
/// "A,K" of MPE_E = A + L/K µm into `budget`.
void parse_mpe_e(const std::string& text, BudgetSpec& budget);
/// "Y=UM,Y=UM,…" (what cmmcomp-vc --qualify --map-only prints) → the qualified reference with
/// the sphere at `sphere_y_mm` (validated).
QualifiedReference parse_reversal_map(const std::string& text, double sphere_y_mm);
/// "Y=PATH" → the model at that path and its Y.
ModelAtY parse_model_at(const std::string& text);

}  // namespace cmmcomp::planning
