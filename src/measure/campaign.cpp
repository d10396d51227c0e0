// SPDX-License-Identifier: MIT
/// @file A campaign as cmmcomp-measure runs it (include/cmmcomp/measure/campaign.hpp).
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/measure/campaign.hpp>
#include <cmmcomp/measure/twin_recording.hpp>
#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace cmmcomp::measure {
namespace {

std::string seconds(double v) { return std::isnan(v) ? "-" : fmt::format("{:.3f} s", v); }

}  // namespace

PlanOptions holdout_plan(const PlanOptions& options, int moves, std::uint64_t seed) {
  PlanOptions held = options;
  held.design = "lhs";
  held.lhs_samples = moves;
  held.repeats = 1;
  held.seed = seed != 0 ? seed : options.seed + 1;
  return held;
}

CampaignRecordings read_campaign_recordings(const std::vector<PlannedMove>& plan,
                                            const std::string& folder,
                                            ExtractOptions& options) {
  CampaignRecordings out;
  if (!std::filesystem::is_directory(folder)) {
    throw ConfigError("--recordings " + folder + ": not a directory");
  }
  const std::string dir = folder + "/";
  const bool session_one = std::filesystem::exists(dir + kSessionFile);
  const bool session_two = std::filesystem::exists(dir + kSessionControllerFile);
  if (!session_one && !session_two) {
    out.moves.reserve(plan.size());
    for (const PlannedMove& m : plan) out.moves.push_back(read_planned_recording(dir, m));
    return out;
  }
  // One continuous recording of the whole plan: the moves are found in it in run order.
  const SessionRecording session =
      read_session_recording(dir + (session_one ? kSessionFile : kSessionControllerFile),
                             session_one ? "" : dir + kSessionTrackerFile,
                             plan.front().axis);
  const SessionSplit split = split_session(plan, session, options);
  out.moves = split.moves;
  if (split.sync.fitted) {
    options.known_clock = true;
    options.clock_offset_s = split.sync.offset_s;
    options.clock_drift = split.sync.drift;
    options.known_clock_source = "sync markers";
  }
  int found = 0;
  for (const MoveRecording& r : out.moves) found += r.problem.empty();
  out.session_line =
      fmt::format("session {}: {} of {} planned moves found", session.source, found, plan.size());
  if (split.sync.fitted) {
    out.session_line +=
        fmt::format(", tracker clock from {} sync markers", split.sync.sync_markers);
  } else if (!session.one_clock) {
    out.session_line +=
        fmt::format(", tracker offset {:.1f} ms from the speeds", split.coarse_offset_s * 1e3);
  }
  return out;
}

std::string format_extraction_outcome(const Extraction& ex,
                                      const std::string& output,
                                      const std::string& report,
                                      const std::string& summary) {
  // Called for a run that was not refused: the moves extracted are those marked ok.
  const auto extracted =
      std::count_if(ex.moves.begin(), ex.moves.end(), [](const MoveExtraction& m) { return m.ok; });
  std::string out =
      fmt::format("extracted {} of {} moves to {}; per-move report: {}; summary: {}\n",
                  extracted,
                  ex.moves.size(),
                  output,
                  report,
                  summary);
  out += fmt::format(
      "controller timing: dwell {} ({}; the traces say {}), smoothing {} ({}; the traces say "
      "{}), over {} moves\n",
      seconds(ex.timing.dwell_s),
      ex.timing.dwell_given ? "given" : "measured",
      seconds(ex.timing.measured_dwell_s),
      seconds(ex.timing.smoothing_s),
      ex.timing.smoothing_given ? "given" : "measured",
      seconds(ex.timing.measured_smoothing_s),
      ex.timing.measured_moves);
  if (ex.clock.source == "motion" && ex.clock.fitted) {
    out += fmt::format(
        "tracker clock: offset {:.3f} ms, drift {:.1f} ppm, from the motion (±{:.3f} ms)\n",
        ex.clock.offset_s * 1e3,
        ex.clock.drift * 1e6,
        ex.clock.uncertainty_ms);
  } else if (ex.clock.source == "sync markers" && ex.clock.sync_markers > 0) {
    out += fmt::format("tracker clock: offset {:.3f} ms, drift {:.1f} ppm, from {} sync markers\n",
                       ex.clock.offset_s * 1e3,
                       ex.clock.drift * 1e6,
                       ex.clock.sync_markers);
  }
  std::map<std::string, int> reasons;
  for (const MoveExtraction& m : ex.moves) {
    if (!m.ok) reasons[m.reason]++;
  }
  for (const auto& [reason, n] : reasons) out += fmt::format("skipped {}: {}\n", n, reason);
  return out;
}

std::string format_nothing_extracted(const Extraction& ex,
                                     const std::string& report,
                                     const std::string& summary) {
  return fmt::format(
      "no move could be extracted; the most frequent reason: {}\n"
      "(controller timing used: dwell {}, smoothing {}; measured on the traces: dwell "
      "{}, smoothing {}; per-move report: {}; summary: {})",
      ex.most_frequent_reason(),
      seconds(ex.timing.dwell_s),
      seconds(ex.timing.smoothing_s),
      seconds(ex.timing.measured_dwell_s),
      seconds(ex.timing.measured_smoothing_s),
      report,
      summary);
}

}  // namespace cmmcomp::measure
