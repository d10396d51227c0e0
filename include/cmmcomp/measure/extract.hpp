// SPDX-License-Identifier: MIT
/// @file Measured traces to the four parameters (`cmmcomp-measure extract`, docs/measurement.md).
///
/// For each planned move: the commanded profile is fitted in time (and offset) to the scale
/// trace, which gives the phase instants on the controller's clock; the tracker's clock is
/// aligned to the controller's from the motion itself (over the rest-to-rest positioning, where
/// an inertial error a/ω² averages out), with a linear drift fitted over the session; the error
/// trace e = (tip − scale)·d, zeroed at rest before the move, then gives MPE, RPE, MAE and RAE by
/// errors::extract_dynamic_errors, the function the twin uses. A move that cannot be extracted is
/// skipped with its reason, never given a wrong row. Offline: allocates, throws ConfigError for
/// malformed files (naming the file and line).
#pragma once

#include <array>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/schema.hpp>
#include <limits>
#include <string>
#include <vector>

namespace cmmcomp::measure {

/// One move's recording. With one clock, the tip samples share the scale's times.
struct MoveRecording {
  int move_id = 0;
  std::string source;                       ///< file name(s), for the report
  std::vector<double> scale_t_s, scale_mm;  ///< controller clock, axis scale reading
  std::vector<double> tip_t_s, tip_mm;  ///< tracker clock (or the controller's), tip on the axis
  /// Sync markers (docs/measurement.md, "Sync"): the times, each on its stream's own clock, of
  /// the rows whose `sync` column is 1. The same trigger in both streams, in the same order.
  std::vector<double> scale_sync_t_s, tip_sync_t_s;
  bool one_clock = true;
  std::string problem;  ///< why there is no usable recording (set by the reader); skips it
};

/// Reads `t_s, x_scale_mm, x_tip_mm` (one clock; the axis letter may be y or z), or, with
/// `tracker_path`, the controller file `t_s, x_scale_mm` and the tracker file `t_s, x_tip_mm`
/// (optionally y_tip_mm, z_tip_mm); either may carry a `sync` column (0, or 1 on a marker row).
/// Times must increase strictly. ConfigError "file:line: ...".
MoveRecording read_move_recording(const std::string& controller_path,
                                  const std::string& tracker_path,
                                  char axis,
                                  int move_id);

/// One planned move's files in the recordings folder `dir` (docs/measurement.md, "Recordings":
/// move-NNNN.csv, or move-NNNN.controller.csv and move-NNNN.tracker.csv), or a recording whose
/// `problem` says why they cannot be read (a missing stream, a malformed file): a bad recording
/// skips its move, never the campaign.
MoveRecording read_planned_recording(const std::string& dir, const PlannedMove& move);

/// The controller timing a move runs with is unknown when it is NaN: extraction measures it.
inline constexpr double kUnknownTiming = std::numeric_limits<double>::quiet_NaN();

/// How the controller runs the moves and when a move (or the run) is refused.
struct ExtractOptions {
  /// The controller's settling dwell at the pre-hit point and its command smoothing [s], as the
  /// user knows them, or kUnknownTiming: both are measured from the scale traces either way, and
  /// a given value the traces contradict by more than `timing_tolerance_s` refuses the run.
  double dwell_s = kUnknownTiming;
  double smoothing_s = kUnknownTiming;
  double timing_tolerance_s = 0.010;       ///< given vs measured timing, and a move vs the run
  double max_profile_rms_um = 50.0;        ///< scale vs the fitted commanded profile
  double max_alignment_residual_ms = 0.5;  ///< a move's clock offset vs the session's fit
  double max_gap_ms = 20.0;                ///< longer tracker dropouts inside a phase skip the move
  /// The approach's speed in the last 10 ms before the planned touch, as a share of AV: a scale
  /// further off triggered early (or late) or hit something.
  double max_touch_speed_error = 0.2;
  /// The tip's travel over a move against the scale's: a ratio further from 1 than this is a
  /// tracker of another unit or sign (per move); a static scale factor (measured at rest in the
  /// dwell) is removed from the error traces, with a warning past `max_scale_factor_ppm`.
  double max_travel_ratio_error = 0.02;
  double max_scale_factor_ppm = 100.0;
  /// A tracker clock known from a synchronisation event (a trigger line, a sync pulse), as
  /// t_controller = (t_tracker + offset) / (1 − drift): used instead of aligning from the motion,
  /// which cannot tell a lag of the tip (drag) from a clock offset.
  bool known_clock = false;
  double clock_offset_s = 0.0;
  double clock_drift = 0.0;
  std::string known_clock_source = "given";  ///< how it is known, for the summary
  /// Aligning two clocks from the motion (no sync, no known clock): the bias the method may
  /// carry (a lag of the tip is indistinguishable from a clock offset: docs/measurement.md) and
  /// the share of Table 1's σ a parameter may move by it before the run is refused.
  double motion_alignment_bias_ms = 0.2;
  double clock_budget_share = 0.5;
  bool accept_clock_uncertainty = false;  ///< warn instead of refusing
  /// More than this share of the moves disagreeing with their plan rows refuses the run as
  /// "recordings of another plan?".
  double max_plan_mismatch_share = 0.5;
};

/// ConfigError naming the first option out of its range (a NaN timing is "unknown", not bad).
void check_extract_options(const ExtractOptions& options);

/// What became of one move.
struct MoveExtraction {
  int move_id = 0;
  bool ok = false;
  std::string reason;                ///< why it was skipped (empty when ok)
  DatasetRow row{};                  ///< the plan's settings and the four measured parameters [µm]
  double start_s = 0;                ///< fitted move start on the controller clock
  double profile_rms_um = 0;         ///< scale vs fitted profile
  double clock_offset_ms = 0;        ///< tracker → controller offset used (0 with one clock)
  double alignment_residual_ms = 0;  ///< this move's own offset minus the session fit's
  int dropouts = 0;                  ///< tracker gaps bridged by interpolation
  double longest_gap_ms = 0;
  double tip_rate_hz = 0;                                           ///< median tracker sample rate
  double dwell_s = std::numeric_limits<double>::quiet_NaN();        ///< measured on this move
  double smoothing_s = std::numeric_limits<double>::quiet_NaN();    ///< measured on this move
  double travel_ratio = std::numeric_limits<double>::quiet_NaN();   ///< tip travel / scale travel
  double rest_noise_um = std::numeric_limits<double>::quiet_NaN();  ///< tip − scale σ at rest
  /// How far each parameter moves for the clock's uncertainty (two clocks aligned from the
  /// motion only) [µm]: MPE, RPE, MAE, RAE.
  std::array<double, 4> clock_sensitivity_um{};
  bool plan_mismatch = false;  ///< skipped because the recording is not its plan row's move
};

/// The session's clock model: t_controller = t_tracker + offset + drift · t_tracker.
struct ClockFit {
  bool fitted = false;  ///< false with one clock or fewer than 3 aligned moves (offset per move)
  double offset_s = 0;
  double drift = 0;             ///< dimensionless (1e-4 = 100 ppm)
  std::string source;           ///< "one clock", "given", "sync markers" or "motion"
  int sync_markers = 0;         ///< marker pairs the sync fit used
  double sync_residual_ms = 0;  ///< largest marker residual of the sync fit
  double uncertainty_ms = 0;    ///< motion alignment: statistical (2σ) plus the method's bias
};

/// The controller timing the extraction used, and what the traces say of it.
struct ControllerTiming {
  double dwell_s = 0, smoothing_s = 0;                                 ///< used
  bool dwell_given = false, smoothing_given = false;                   ///< used = the user's value
  double measured_dwell_s = std::numeric_limits<double>::quiet_NaN();  ///< campaign median
  double measured_smoothing_s = std::numeric_limits<double>::quiet_NaN();  ///< campaign median
  int measured_moves = 0;
};

/// The campaign's noise (docs/measurement.md, "Noise").
struct NoiseEstimate {
  double rest_um = std::numeric_limits<double>::quiet_NaN();  ///< tip − scale σ at rest, median
  /// Pooled standard deviation of each parameter over the repeats of each run [µm], with its
  /// degrees of freedom (0: no repeats).
  std::array<double, 4> repeat_sd_um{};
  int repeat_dof = 0;
};

/// The extraction of a whole plan.
struct Extraction {
  std::vector<MoveExtraction> moves;  ///< one per recording, in plan order
  ClockFit clock;
  ControllerTiming timing;
  NoiseEstimate noise;
  double travel_ratio = std::numeric_limits<double>::quiet_NaN();  ///< median over the moves
  /// The static scale factor k removed from every error trace: the slope over PD of tip − scale
  /// at rest in the dwell (against at rest before the move), fitted with a constant over the
  /// moves whose dwell is at least 0.1 s; NaN when PD does not vary by 20 % or no dwell is.
  double scale_factor = std::numeric_limits<double>::quiet_NaN();
  int scale_factor_moves = 0;
  std::string axis;  ///< the plan's axis ("x", "y", "z"), empty when its moves differ
  /// Why the whole run is refused (empty: it is not): the dataset must not be written.
  std::string refusal;
  /// `warning:` lines for stderr: cause, evidence and fix.
  std::vector<std::string> warnings;
  /// The rows of the extracted moves, for the dataset CSV; none when the run is refused.
  std::vector<DatasetRow> rows() const;
  /// The most frequent skip reason, with its count ("54 of 54 moves: ...").
  std::string most_frequent_reason() const;
};

/// Extracts every recording against its planned move (matched by move_id; a recording of a
/// move not in the plan is skipped with a reason).
Extraction extract_moves(const std::vector<PlannedMove>& plan,
                         const std::vector<MoveRecording>& recordings,
                         const ExtractOptions& options);

/// One continuous recording of a whole session: the scale log, and the tracker's (on its own
/// clock, or the same samples with one clock).
struct SessionRecording {
  std::string source;
  std::vector<double> scale_t_s, scale_mm;
  std::vector<double> tip_t_s, tip_mm;
  std::vector<double> scale_sync_t_s, tip_sync_t_s;  ///< sync markers, as in MoveRecording
  bool one_clock = true;
};

/// The tracker clock from sync markers: the i-th marker of each stream is the same trigger;
/// t_controller = a + b · t_tracker fitted over the pairs (one pair: the offset alone). Returns
/// a ClockFit in ExtractOptions' convention with `source` "sync markers"; not fitted when either
/// stream has none. ConfigError when the counts differ or a pair is off the fit by more than
/// 0.05 ms (markers that are not the same triggers).
ClockFit sync_clock(const std::vector<double>& scale_markers_s,
                    const std::vector<double>& tip_markers_s,
                    const std::string& source);

/// Reads a session: `session.csv` with `t_s, x_scale_mm, x_tip_mm`, or, with `tracker_path`,
/// the controller's `t_s, x_scale_mm` and the tracker's `t_s, x_tip_mm`.
SessionRecording read_session_recording(const std::string& controller_path,
                                        const std::string& tracker_path,
                                        char axis);

/// The session cut into the planned moves (docs/measurement.md, "Session recordings"): the
/// tracker's clock from the sync markers when both streams carry them, else its coarse offset
/// from the cross-correlation of the two streams' speeds over windows around the first moves
/// (a bounded grid, whatever the log's span); a time that jumps by more than an hour between
/// two rows is a ConfigError naming the row. Then,
/// in run order, each move found by motion detection in the scale log, at rest at its start
/// and then moving PD/2 towards the point, and cut from 0.25 s before it moves (or its rest's
/// start) to 50 ms after its planned touch. A move not found gets a `problem` (and is skipped).
struct SessionSplit {
  std::vector<MoveRecording> moves;  ///< one per planned move, in plan order
  double coarse_offset_s = 0;        ///< tracker → controller, from the speeds (or the sync)
  ClockFit sync;                     ///< the clock from the session's sync markers, if any
};
SessionSplit split_session(const std::vector<PlannedMove>& plan,
                           const SessionRecording& session,
                           const ExtractOptions& options);

/// The per-move report as CSV: move_id, status, reason and the figures above.
std::string format_extraction_report(const Extraction& extraction);

/// The campaign summary as JSON (docs/measurement.md, "Campaign summary"): moves extracted and
/// skipped by reason, the controller timing used and measured, the clock, the travel ratio, the
/// noise per parameter against Table 1's σ, the refusal and the warnings.
std::string format_extraction_summary(const Extraction& extraction);

/// `format` of the campaign summary JSON.
inline constexpr const char* kSummaryFormat = "cmmcomp-extraction-summary";

/// What cmmcomp-train reads back from a campaign summary to record the model's training
/// conditions: the controller timing the moves ran with, the axis, the repeat noise.
struct CampaignSummary {
  std::string source;   ///< the file
  std::string axis;     ///< empty: not one axis
  std::string refusal;  ///< non-empty: the campaign was refused
  int extracted = 0;
  double dwell_s = std::numeric_limits<double>::quiet_NaN();      ///< used (given or measured)
  double smoothing_s = std::numeric_limits<double>::quiet_NaN();  ///< used (given or measured)
  /// Repeat σ per parameter (MPE, RPE, MAE, RAE) [µm]; NaN without repeats.
  std::array<double, 4> repeat_sd_um{};
};

/// Parses a campaign summary (format_extraction_summary's text). ConfigError naming the source
/// and the missing or malformed key.
CampaignSummary parse_extraction_summary(const std::string& text, const std::string& source);
/// Reads a campaign summary file (at most 1 MiB) as parse_extraction_summary.
CampaignSummary read_extraction_summary(const std::string& path);

/// The training conditions that campaigns state (for the model file, io::TrainingConditions):
/// the controller dwell and smoothing they ran with, their common axis, and the noise floor, the
/// repeat σ of each parameter pooled over the campaigns (unknown when any has no repeats).
/// ConfigError when a campaign was refused, or when two disagree on the timing by more than
/// `timing_tolerance_s` or on the axis (one model is trained at one setting, on one axis).
io::TrainingConditions campaign_conditions(const std::vector<CampaignSummary>& campaigns,
                                           double timing_tolerance_s = 0.010);

/// The campaign summary as a gnuplot script (pngcairo, its data inline) that draws `png_path`:
/// the controller timing measured per move against the run's, each parameter's repeat σ against
/// Table 1's, the moves extracted and skipped by reason, and the verdict in the title.
std::string campaign_plot_script(const Extraction& extraction, const std::string& png_path);

}  // namespace cmmcomp::measure
