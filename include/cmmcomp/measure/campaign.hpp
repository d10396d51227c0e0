// SPDX-License-Identifier: MIT
/// @file A campaign on a real machine as cmmcomp-measure runs it (docs/measurement.md): the
/// held-out plan next to the training plan, reading a campaign's recordings whichever way they
/// were taken, and what extraction tells the user.
///
/// Contract: read_campaign_recordings() takes one continuous session when the folder holds
/// session files (split into the plan's moves in run order; its sync markers, when fitted, set
/// the options' known clock), otherwise one file per planned move; ConfigError for a folder
/// that does not exist or a file that cannot be read. The formatters write the lines the tool
/// prints. Setup-time code.
#pragma once

#include <cmmcomp/measure/extract.hpp>
#include <cmmcomp/measure/plan.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::measure {

/// The plan of the held-out check: `moves` Latin-hypercube moves over the same box, one
/// repeat, seed `seed` (0: the plan's seed + 1).
PlanOptions holdout_plan(const PlanOptions& options, int moves, std::uint64_t seed);

/// A campaign's recordings, one per planned move (a move not found carries its problem).
struct CampaignRecordings {
  std::vector<MoveRecording> moves;
  /// One line about the session ("session …: 54 of 54 planned moves found, …"); empty when
  /// the recordings were one file per move.
  std::string session_line;
};

/// Reads the recordings of `plan` from the folder `dir` (see the file comment).
CampaignRecordings read_campaign_recordings(const std::vector<PlannedMove>& plan,
                                            const std::string& dir,
                                            ExtractOptions& options);

/// After a run that wrote the dataset `output`, the report and the summary: the moves
/// extracted, the controller timing used and measured, the tracker clock, the moves skipped by
/// reason.
std::string format_extraction_outcome(const Extraction& ex,
                                      const std::string& output,
                                      const std::string& report,
                                      const std::string& summary);
/// Why no move could be extracted: the most frequent reason and the timing used and measured.
std::string format_nothing_extracted(const Extraction& ex,
                                     const std::string& report,
                                     const std::string& summary);

}  // namespace cmmcomp::measure
