// SPDX-License-Identifier: MIT
/// @file The log lines of a server's refused requests and outside-domain answers, rate-limited.
///
/// A server's request handler pushes every refused request and every answer outside the model's
/// domain into a compensation::ServerOutcomeLog (RT-safe). An OutcomeLogger, on another thread,
/// pops them and writes one line per event with the move and the reason, at most `per_second`
/// lines per second; what it does not print it counts, and says so in one summary line when the
/// second is over. Nothing is lost silently: events the ring had to drop are counted too.
#pragma once

#include <chrono>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <cstdint>
#include <functional>
#include <string>

namespace cmmcomp::serving {

/// "refused (outside the domain) axis 0: PV 1e+06 mm/s, PD 60 mm, …: <what it means>".
std::string describe_outcome(const compensation::OutcomeEvent& event);

/// See the file comment. One logger per log; not thread-safe (one draining thread).
class OutcomeLogger {
 public:
  using Clock = std::chrono::steady_clock;
  using Sink = std::function<void(const std::string& line)>;

  /// Lines go to `sink` (default: spdlog::warn), prefixed with `server` ("modbus tcp://…: ").
  OutcomeLogger(std::string server,
                compensation::ServerOutcomeLog& log,
                int per_second = 5,
                Sink sink = {});

  /// Pops every event and writes the lines the budget allows at `now`; at the end of a second
  /// in which lines were suppressed, one line says how many. Call it periodically and once when
  /// the server has stopped.
  void drain(Clock::time_point now);
  /// Drains, then writes the summary line of the last second's suppressed lines, if any: the
  /// call after the server has stopped.
  void finish(Clock::time_point now);

  std::uint64_t events() const { return events_; }          ///< events popped
  std::uint64_t suppressed() const { return suppressed_; }  ///< of those, not printed
  /// Events the ring dropped because the logger was too slow.
  std::uint64_t dropped() const { return log_.dropped(); }

 private:
  std::string server_;
  compensation::ServerOutcomeLog& log_;
  int per_second_;
  Sink sink_;
  Clock::time_point window_start_{};
  int window_lines_ = 0;
  std::uint64_t window_suppressed_ = 0;
  std::uint64_t events_ = 0, suppressed_ = 0, dropped_reported_ = 0;
};

}  // namespace cmmcomp::serving
