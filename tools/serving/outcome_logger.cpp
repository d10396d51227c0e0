// SPDX-License-Identifier: MIT
/// @file OutcomeLogger: the agent's log of refused requests and outside-domain answers.
#include "outcome_logger.hpp"

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include <utility>

namespace cmmcomp::serving {

std::string describe_outcome(const compensation::OutcomeEvent& e) {
  const compensation::MoveRequest& m = e.move;
  const char* what = "";
  switch (e.status) {
    case Status::kOutsideDomain:
      what =
          "answered OUTSIDE the model's domain: an input, PA or AA lies beyond what the model "
          "was trained at, so the correction is less sure than its U95 says (docs/compensator.md, "
          "\"Domain\"); train at these settings, or set outside_domain = reject";
      break;
    case Status::kOutsideDomainRejected:
      what =
          "refused: outside the model's domain (policy reject), or far outside it under any "
          "policy (docs/compensator.md, \"Domain\")";
      break;
    case Status::kNoModel:
      what = "refused: no model is published for this axis";
      break;
    default:
      what = "refused: the request is not a valid move";
      break;
  }
  return fmt::format(
      "sequence {} axis {}: PV {:g} mm/s, PD {:g} mm, AV {:g} mm/s, AD {:g} mm, PA {:g} mm/s², "
      "AA {:g} mm/s², Y {:g} mm, Z {:g} mm, d ({:g}, {:g}, {:g}): {}",
      m.sequence,
      static_cast<int>(m.axis),
      m.pv_mm_s,
      m.pd_mm,
      m.av_mm_s,
      m.ad_mm,
      m.pa_mm_s2,
      m.aa_mm_s2,
      m.y_mm,
      m.z_mm,
      m.direction[0],
      m.direction[1],
      m.direction[2],
      what);
}

OutcomeLogger::OutcomeLogger(std::string server,
                             compensation::ServerOutcomeLog& log,
                             int per_second,
                             Sink sink)
    : server_(std::move(server)),
      log_(log),
      per_second_(per_second < 1 ? 1 : per_second),
      sink_(sink ? std::move(sink)
                 : Sink([](const std::string& line) { spdlog::warn("{}", line); })) {}

void OutcomeLogger::finish(Clock::time_point now) {
  drain(now);
  drain(now + std::chrono::seconds(1));  // closes the window: its summary line, if any
}

void OutcomeLogger::drain(Clock::time_point now) {
  const auto close_window = [&] {
    if (window_suppressed_ > 0) {
      sink_(
          fmt::format("{}: {} more refused or outside-domain answers in that second were not "
                      "logged ({} in all so far; the counters at the end have every one)",
                      server_,
                      window_suppressed_,
                      suppressed_));
    }
    window_start_ = now;
    window_lines_ = 0;
    window_suppressed_ = 0;
  };
  if (now - window_start_ >= std::chrono::seconds(1)) close_window();
  compensation::OutcomeEvent e;
  while (log_.pop(e)) {
    ++events_;
    if (window_lines_ < per_second_) {
      ++window_lines_;
      sink_(server_ + ": " + describe_outcome(e));
    } else {
      ++window_suppressed_;
      ++suppressed_;
    }
  }
  const std::uint64_t dropped = log_.dropped();
  if (dropped > dropped_reported_) {
    sink_(
        fmt::format("{}: {} refused or outside-domain answers came faster than the log could "
                    "take them and are only counted",
                    server_,
                    dropped - dropped_reported_));
    dropped_reported_ = dropped;
  }
}

}  // namespace cmmcomp::serving
