// SPDX-License-Identifier: MIT
/// @file The replay loop: every recorded request goes to a Session, its answers are compared
/// with the recorded ones byte for byte, and the first difference is explained field by field.
#pragma once

#include <cstddef>
#include <cstdint>
#include <ostream>
#include <string>
#include <vector>

#include "recording.hpp"
#include "session.hpp"

namespace cmmcomp::replay {

struct ReplayOptions {
  /// Stop after this many mismatching requests; 0 = replay everything. Default: the first.
  std::size_t max_mismatches = 1;
  /// Print one line per request that has answers (recorded or replayed) to the text stream.
  bool verbose = true;
};

/// One request whose answers differ from the recorded ones.
struct Mismatch {
  int request_line = 0;  ///< line of the request in the recording
  int line = 0;          ///< line of the first differing recorded answer (0: none recorded)
  std::string request;   ///< the request as recorded
  std::string request_summary;
  std::size_t answer_index = 0;  ///< which answer (0-based) differs first
  std::size_t answers_expected = 0;
  std::size_t answers_actual = 0;
  std::string expected;   ///< that answer, recorded ("" when missing)
  std::string actual;     ///< that answer, replayed ("" when missing)
  long byte_offset = -1;  ///< first differing byte in the answer; -1: the count or the id differ
  std::string field;      ///< the field at byte_offset, e.g. "RAE (bytes 21-24)"
  std::vector<std::string> differences;  ///< "RAE -5.298 µm recorded vs -5.301 µm replayed", …
  std::string expected_summary;
  std::string actual_summary;
};

/// One request that had answers (recorded or replayed), as the text report prints it.
struct ExchangeLine {
  int line = 0;         ///< line of the request
  std::string request;  ///< summary of the request
  std::string answer;   ///< summary of the replayed answer
  bool match = false;
};

struct ReplayResult {
  std::string source;
  std::string format;
  std::string target;
  std::size_t requests = 0;    ///< request messages replayed
  std::size_t answers = 0;     ///< recorded answers compared
  std::size_t matched = 0;     ///< requests whose answers all matched
  std::size_t heartbeats = 0;  ///< skipped heartbeat frames
  std::size_t other = 0;       ///< skipped messages not addressed to or from the plugin
  bool stopped_early = false;  ///< max_mismatches reached before the end
  std::vector<Mismatch> mismatches;
  std::vector<ExchangeLine> exchanges;  ///< in order; requests without any answer are left out
};

/// Replays `recording` through `session`. Per request (when options.verbose) a line
/// "LINE: REQUEST -> ANSWER: match|MISMATCH" goes to `text` (may be nullptr). Throws
/// cmmcomp::Error when a live target fails.
ReplayResult run_replay(const Recording& recording,
                        Session& session,
                        const ReplayOptions& options,
                        std::ostream* text);

/// The report of a mismatch, several lines, for people.
std::string format_mismatch(const std::string& source, const Mismatch& m);

/// The whole result as JSON (one object), for scripts.
std::string result_json(const ReplayResult& r);

}  // namespace cmmcomp::replay
