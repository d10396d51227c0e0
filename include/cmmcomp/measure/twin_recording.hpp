// SPDX-License-Identifier: MIT
/// @file A measurement campaign on the twin: each planned move simulated, then recorded as a
/// real set-up would record it (`cmmcomp-sim record`, docs/measurement.md): the controller's
/// scale log at its rate, and the tracker on its own clock (offset, drift), at its own rate,
/// with white and 1/f noise and dropouts. The moves run back to back in run order with a rest
/// between them, on one session clock, so the recordings carry session timestamps.
#pragma once

#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::measure {

/// How the controller and the tracker record.
struct RecordingSetup {
  double controller_rate_hz = 1000.0;  ///< scale log rate
  double tracker_rate_hz = 1000.0;     ///< tracker rate (its own clock)
  bool two_clocks = false;             ///< false: one file per move, the tip on the scale's times
  double clock_offset_s = 0.0;         ///< t_tracker = (t_controller − offset)·(1 − drift)…
  double drift = 0.0;             ///< …so that extraction's t_c = (t_t + offset)/(1 − drift)
  double white_noise_um = 0.0;    ///< tracker white noise, standard deviation
  double pink_noise_um = 0.0;     ///< tracker 1/f noise, standard deviation
  double dropout_fraction = 0.0;  ///< share of tracker samples lost, in short bursts
  /// Uneven tracker sampling (two clocks only): each sample is taken, and time-stamped, at its
  /// nominal time plus a uniform offset of ± this share of the tracker period, in [0, 0.45].
  double tracker_jitter = 0.0;
  double rest_s = 0.3;  ///< rest before each move (and between moves)
  /// A sync marker in both streams (two clocks): one trigger per move, 0.1 s into its rest,
  /// recorded as an extra row at the trigger's instant on each clock with `sync` = 1
  /// (docs/measurement.md, "Sync"), as a tracker's external trigger input records it.
  bool sync = false;
  std::uint64_t seed = 1;
};

/// One move of the campaign: its recording and the twin's exact four parameters.
struct TwinMove {
  MoveRecording recording;
  errors::DynamicErrors exact_um;  ///< noiseless, from the twin
};

/// Simulates every planned move (in the plan's order) on `machine` and records it per `setup`.
/// Throws Error when a move cannot be simulated.
std::vector<TwinMove> record_on_twin(const dynamics::Machine& machine,
                                     const std::vector<PlannedMove>& plan,
                                     const RecordingSetup& setup);

/// Writes one move's files into `dir`: move-NNNN.csv (one clock) or move-NNNN.controller.csv
/// and move-NNNN.tracker.csv (docs/measurement.md, "Recordings").
void write_move_recording(const std::string& dir, const MoveRecording& recording, char axis);

/// The moves' recordings as one session (they are consecutive on the session clock), and its
/// files: session.csv (one clock) or session.controller.csv and session.tracker.csv.
SessionRecording as_session(const std::vector<TwinMove>& moves);
void write_session_recording(const std::string& dir, const SessionRecording& session, char axis);
inline constexpr const char* kSessionFile = "session.csv";
inline constexpr const char* kSessionControllerFile = "session.controller.csv";
inline constexpr const char* kSessionTrackerFile = "session.tracker.csv";

/// The file names write_move_recording uses for `move_id`.
std::string one_clock_file(int move_id);
std::string controller_file(int move_id);
std::string tracker_file(int move_id);

}  // namespace cmmcomp::measure
