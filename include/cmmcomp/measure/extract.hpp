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

#include <cmmcomp/measure/plan.hpp>
#include <cmmcomp/schema.hpp>
#include <string>
#include <vector>

namespace cmmcomp::measure {

/// One move's recording. With one clock, the tip samples share the scale's times.
struct MoveRecording {
  int move_id = 0;
  std::string source;                       ///< file name(s), for the report
  std::vector<double> scale_t_s, scale_mm;  ///< controller clock, axis scale reading
  std::vector<double> tip_t_s, tip_mm;  ///< tracker clock (or the controller's), tip on the axis
  bool one_clock = true;
  std::string problem;  ///< why there is no usable recording (set by split_session); skips it
};

/// Reads `t_s, x_scale_mm, x_tip_mm` (one clock; the axis letter may be y or z), or, with
/// `tracker_path`, the controller file `t_s, x_scale_mm` and the tracker file `t_s, x_tip_mm`
/// (optionally y_tip_mm, z_tip_mm). Times must increase strictly. ConfigError "file:line: ...".
MoveRecording read_move_recording(const std::string& controller_path,
                                  const std::string& tracker_path,
                                  char axis,
                                  int move_id);

/// How the controller runs the moves and when a move is refused.
struct ExtractOptions {
  double dwell_s = 0.0;                    ///< the controller's settling dwell at the pre-hit point
  double smoothing_s = 0.0;                ///< the controller's command smoothing
  double max_profile_rms_um = 50.0;        ///< scale vs the fitted commanded profile
  double max_alignment_residual_ms = 0.5;  ///< a move's clock offset vs the session's fit
  double max_gap_ms = 20.0;                ///< longer tracker dropouts inside a phase skip the move
  /// A tracker clock known from a synchronisation event (a trigger line, a sync pulse), as
  /// t_controller = (t_tracker + offset) / (1 − drift): used instead of aligning from the motion,
  /// which cannot tell a lag of the tip (drag) from a clock offset.
  bool known_clock = false;
  double clock_offset_s = 0.0;
  double clock_drift = 0.0;
};

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
  double tip_rate_hz = 0;  ///< median tracker sample rate
};

/// The session's clock model: t_controller = t_tracker + offset + drift · t_tracker.
struct ClockFit {
  bool fitted = false;  ///< false with one clock or fewer than 3 aligned moves (offset per move)
  double offset_s = 0;
  double drift = 0;  ///< dimensionless (1e-4 = 100 ppm)
};

/// The extraction of a whole plan.
struct Extraction {
  std::vector<MoveExtraction> moves;  ///< one per recording, in plan order
  ClockFit clock;
  /// The rows of the extracted moves, for the dataset CSV.
  std::vector<DatasetRow> rows() const;
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
  bool one_clock = true;
};

/// Reads a session: `session.csv` with `t_s, x_scale_mm, x_tip_mm`, or, with `tracker_path`,
/// the controller's `t_s, x_scale_mm` and the tracker's `t_s, x_tip_mm`.
SessionRecording read_session_recording(const std::string& controller_path,
                                        const std::string& tracker_path,
                                        char axis);

/// The session cut into the planned moves (docs/measurement.md, "Session recordings"): the
/// tracker's coarse clock offset from the cross-correlation of the two streams' speeds; then,
/// in run order, each move found by motion detection in the scale log, at rest at its start
/// and then moving PD/2 towards the point, and cut from 0.25 s before it moves (or its rest's
/// start) to 50 ms after its planned touch. A move not found gets a `problem` (and is skipped).
struct SessionSplit {
  std::vector<MoveRecording> moves;  ///< one per planned move, in plan order
  double coarse_offset_s = 0;        ///< tracker → controller, from the speeds
};
SessionSplit split_session(const std::vector<PlannedMove>& plan,
                           const SessionRecording& session,
                           const ExtractOptions& options);

/// The per-move report as CSV: move_id, status, reason and the figures above.
std::string format_extraction_report(const Extraction& extraction);

}  // namespace cmmcomp::measure
