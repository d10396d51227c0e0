// SPDX-License-Identifier: MIT
/// @file The whole probing cycle's speed-up (issue 38, §3–§4): the fastest cycle a qualified
/// uncompensated machine can run at a point-error budget against the fastest a compensated one
/// can, both with the same controller freedom (every setting the machine's capabilities allow:
/// PV, PA, AV, AA, AD, the dwell and the smoothing; PD is the program's), judged on the twin.
///
/// The rules, the same for both kinds (docs/study.md, "The whole cycle"):
///  - a cycle's time is MoveProfile's, from the start of the positioning to the touch, with its
///    own dwell and smoothing;
///  - its touch must come at constant approach speed (the approach reaches AV before the touch)
///    and its |MAE| must stay within the overtravel limit at every Y;
///  - what is left of each touch, plus the repeatability at 95 % (k σ √(1 + share), share: the
///    reversal map's and the qualification's own scatter), must stay within the budget at every
///    Y of the program:
///      qualified uncompensated: residual(Y) = (RAE(Y) − RAE(sphere)) − (map(Y) − map(sphere))
///        (planning/qualified_reference.hpp), on the machine *and* on each of its robustness
///        variants (its mode frequency ±2 %, damping ±20 %, hose time constant ±10 % and
///        delayed-acceleration term ±20 %, map and qualification redone on each): a pass of the
///        nominal machine alone is often a transient crossing zero at the touch;
///      compensated: RAE_truth(Y) − RAE_model(Y), the model's whole prediction subtracted
///        (vc/qualification.hpp: a compensated touch is not qualified).
/// The model is a machine: the truth itself (the oracle: a perfect model, the bound), or a
/// machine identified from a campaign on the truth (the grey-box model: identified physics).
/// The search walks a grid of cycles in order of time and stops at the first that passes, so
/// the answer is the grid's fastest passing cycle.
///
/// Setup-time code: allocates, simulates, throws ConfigError for an empty grid or bad rules.
#pragma once

#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/study/acceptance.hpp>
#include <cmmcomp/vc/probe_setting.hpp>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace cmmcomp::study {

/// How a cycle is judged (file comment). Units: µm and mm.
struct CycleRules {
  double budget_um = 0.0;  ///< per point at 95 % (0: half of MPE_E at 20 mm, the planner's)
  double sigma_um = 0.0;   ///< RAE's repeatability σ (0: the paper's Table 1)
  double k95 = 1.96;       ///< coverage factor of the 95 % bound
  /// The reversal map's and the qualification's scatter, as a share of the touch's variance:
  /// the vc averages 10 touches for each and removes both (σ² (1 + 1/10 + … ) ≈ 1.3 σ²).
  double scatter_share = 0.3;
  double mae_limit_um = 25.0;                   ///< |MAE| at every Y: the probe's overtravel
  std::vector<double> y_mm{0.0, 250.0, 500.0};  ///< the program's carriage positions
  double sphere_y_mm = 250.0;                   ///< where the probe is qualified
  vc::ProbeSetting map_setting = vc::default_slow_setting();  ///< the reversal map's setting

  /// The budget left for the deterministic residual [µm]: budget − k σ √(1 + share).
  double allowance_um() const;
  /// Fills the defaults; throws ConfigError when a value is not finite, the allowance is not
  /// positive, or there is no Y.
  CycleRules resolved() const;
};

/// The levels searched of each setting (mm, mm/s, mm/s², s): every combination is a cycle.
struct CycleGrid {
  std::vector<double> pv_mm_s, pa_mm_s2, av_mm_s, aa_mm_s2, ad_mm, dwell_s, smoothing_s;
};

/// A grid over what `machine`'s capabilities allow: PV and AV on a few levels each, PA and AA
/// at three, AD from the smallest allowed, the dwell from 0 to the controller's own, the
/// smoothing at 0, one period of the first mode (its notch) and the controller's own.
CycleGrid default_cycle_grid(const dynamics::Machine& machine);

/// The four touches of a machine variant and the constraint a cycle meets worst.
struct CycleCheck {
  bool passes = false;
  double residual_um = 0.0;   ///< the largest |residual| over Y (and variants) [µm]
  double worst_y_mm = 0.0;    ///< where
  std::string worst_machine;  ///< on which machine (the truth or a variant's name)
  double mae_um = 0.0;        ///< the largest |MAE| over Y (and variants) [µm]
  bool constant_speed_touch = false;
  /// The constraint closest to its limit: "residual at Y … on …", "MAE", or "constant-speed
  /// touch"; for a failing cycle, the first one violated.
  std::string binding;
};

/// The fastest passing cycle of a grid.
struct CycleChoice {
  bool found = false;
  motion::ProbingMove cycle;  ///< SI, with its dwell and smoothing
  double time_s = 0.0;        ///< its time per point
  CycleCheck check;
  long judged = 0;  ///< cycles simulated before it (the grid's faster ones that failed, + 1)
};

/// The qualified uncompensated machine's fastest cycle at `pd_mm` (file comment), robust over
/// `variants` (robustness_variants() of the truth, say).
CycleChoice fastest_qualified_cycle(const dynamics::Machine& truth,
                                    const std::vector<dynamics::Machine>& variants,
                                    double pd_mm,
                                    const CycleGrid& grid,
                                    const CycleRules& rules);

/// The machine compensated by `model`'s predictions: its fastest cycle at `pd_mm`.
CycleChoice fastest_compensated_cycle(const dynamics::Machine& truth,
                                      const dynamics::Machine& model,
                                      double pd_mm,
                                      const CycleGrid& grid,
                                      const CycleRules& rules);

/// The truth with its mode frequency ±2 %, damping ±20 %, hose time constant ±10 % and
/// delayed-acceleration term ±20 %, one at a time (8 machines, each named for its change).
std::vector<dynamics::Machine> robustness_variants(const dynamics::Machine& truth);

/// Time per point of the slowest-but-qualified reference the project started from
/// (docs/planner.md): what "≥ 3.5× against today's reference" divides [s].
double todays_qualified_reference_s();

/// What the comparison runs on: a truth machine and, optionally, the model identified for it.
struct CycleSubject {
  dynamics::Machine truth;
  bool has_model = false;
  dynamics::Machine model;
};

/// The campaign a grey-box model is identified from: `moves` traced moves (their four
/// parameters, with Table 1 noise of `seed`) on a Latin hypercube over the machine's
/// capabilities (PV, PD 5–300 mm, AV, AD, PA, AA) and Y 0–500 mm, at the controller's own
/// timing (which the recordings measure: the start takes the truth's dwell and smoothing); then
/// training::identify_machine from `start` with `free_parameters` (the physics a model of this
/// twin's structure has: the first mode, the hose; never the second mode or the frequency's
/// change along the beam).
struct CampaignIdentification {
  int moves = 150;
  std::uint64_t seed = 1;
  dynamics::Machine start;  ///< where the fit starts (the shipped start file, say)
  /// The fit runs from the start's mode frequency times each of these (outside the plausible
  /// range: skipped) and keeps the lowest cost: the objective has a minimum per frequency.
  std::vector<double> frequency_starts{0.6, 0.8, 1.0, 1.25};
  /// The keys fitted: the first mode and the hose, the Coulomb drag's regularisation speed
  /// included (a start file's guess of it, held fixed, leaves the fit a systematic misfit).
  std::vector<std::string> free_parameters{"structure.mode_frequency_hz",
                                           "structure.participation",
                                           "structure.shape_growth",
                                           "hose.time_constant_s",
                                           "hose.viscous_drag_Ns_per_m",
                                           "hose.coulomb_drag_N",
                                           "hose.coulomb_speed_m_per_s",
                                           "hose.accel_lag_s2"};
};

/// The identified machine, named "<truth> identified", and the fit's parameter uncertainties.
struct IdentifiedModel {
  dynamics::Machine machine;
  std::vector<std::string> parameters;  ///< the fitted keys
  std::vector<double> truth_values;     ///< each key's value in the truth
  std::vector<double> fitted_values;
  std::vector<double> relative_sigma;  ///< 1σ / value (training::IdentificationReport)
  double final_cost = 0.0;
  double truth_cost = 0.0;  ///< the truth's own cost on the campaign (the noise's): the floor
  int residuals = 0;        ///< of the fit (4 per move)
};

/// Identifies `truth` from its campaign (above). Throws what identify_machine throws.
IdentifiedModel identify_from_campaign(const dynamics::Machine& truth,
                                       const CampaignIdentification& campaign);

/// One machine and PD of the comparison.
struct CycleSpeedupRow {
  std::string machine;
  double pd_mm = 0.0;
  CycleChoice qualified;   ///< the qualified uncompensated machine, same freedom
  CycleChoice oracle;      ///< compensated by the truth itself (the bound)
  CycleChoice identified;  ///< compensated by the identified machine (when one is given)
  bool has_identified = false;
  /// The virtual controller's length test (vc::run_length_test, every Y of the rules) of the
  /// chosen cycles on the truth with Table 1 noise, one run per seed 1 … length_test_seeds:
  /// the seeds at which every Y met MPE_E, qualified (uncompensated columns qualified) and
  /// compensated (corrected by the identified machine through vc::TwinSource).
  int length_test_seeds = 0;
  int qualified_seeds_passed = 0;
  int identified_seeds_passed = 0;
};

struct CycleSpeedupResult {
  CycleRules rules;  ///< resolved
  std::vector<CycleSpeedupRow> rows;
  std::vector<IdentifiedModel> identified;  ///< the models identified from campaigns
  std::vector<Target> targets;
};

/// The seeds 1 … `seeds` at which the length test of `cycle` on `truth` (at the cycle's own
/// timing) met MPE_E at every Y of `y_mm`: uncompensated and qualified when `model` is null,
/// else compensated by `model` (vc::TwinSource at the same timing).
int length_test_passes(const dynamics::Machine& truth,
                       const dynamics::Machine* model,
                       const motion::ProbingMove& cycle,
                       const std::vector<double>& y_mm,
                       int seeds);

/// Every subject at every PD. Targets per row with a model: compensated/qualified ≥ 1.4 and
/// today's reference/compensated ≥ 3.5 (issue 38 §4), and both chosen cycles pass the length
/// test at every seed of `length_test_seeds`. With `campaign`, a subject without a model gets
/// one identified from its campaign (identify_from_campaign()). `progress` gets a line per step.
CycleSpeedupResult cycle_speedup(const std::vector<CycleSubject>& subjects,
                                 const std::vector<double>& pd_mm,
                                 const CycleRules& rules,
                                 const CampaignIdentification* campaign = nullptr,
                                 const std::function<void(const std::string&)>& progress = {},
                                 int length_test_seeds = 5);

}  // namespace cmmcomp::study
