// SPDX-License-Identifier: MIT
/// @file The agent's log of refused requests and outside-domain answers (docs/agent.md, "Log"):
/// one line per event with the move and the reason, at most N a second, the rest counted and
/// summarised, and what the ring dropped reported.
#include <gtest/gtest.h>

#include <chrono>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <string>
#include <vector>

#include "outcome_logger.hpp"

namespace cmmcomp::serving {
namespace {

compensation::OutcomeEvent event(std::uint32_t sequence, Status status) {
  compensation::OutcomeEvent e;
  e.move.sequence = sequence;
  e.move.axis = 1;
  e.move.direction = {-1.0, 0.0, 0.0};
  e.move.pv_mm_s = 1e6;
  e.move.pa_mm_s2 = 1200.0;
  e.move.pd_mm = 60.0;
  e.move.av_mm_s = 12.0;
  e.move.aa_mm_s2 = 60.0;
  e.move.ad_mm = 10.0;
  e.status = status;
  return e;
}

TEST(OutcomeLogger, NamesTheMoveAndTheReason) {
  const std::string refused = describe_outcome(event(7, Status::kOutsideDomainRejected));
  EXPECT_NE(refused.find("sequence 7 axis 1: PV 1e+06 mm/s"), std::string::npos) << refused;
  EXPECT_NE(refused.find("PA 1200 mm/s²"), std::string::npos) << refused;
  EXPECT_NE(refused.find("refused: outside the model's domain"), std::string::npos) << refused;
  EXPECT_NE(describe_outcome(event(1, Status::kOutsideDomain)).find("answered OUTSIDE"),
            std::string::npos);
  EXPECT_NE(describe_outcome(event(1, Status::kNoModel)).find("no model"), std::string::npos);
  EXPECT_NE(describe_outcome(event(1, Status::kInvalidInput)).find("not a valid move"),
            std::string::npos);
}

TEST(OutcomeLogger, RateLimitsAndSaysWhatItDidNotPrint) {
  compensation::ServerOutcomeLog log;
  std::vector<std::string> lines;
  OutcomeLogger logger("modbus test", log, 3, [&](const std::string& l) { lines.push_back(l); });
  const auto t0 = OutcomeLogger::Clock::time_point{} + std::chrono::hours(1);
  for (std::uint32_t k = 0; k < 10; ++k) log.push(event(k, Status::kOutsideDomainRejected));
  logger.drain(t0);
  ASSERT_EQ(lines.size(), 3u);
  EXPECT_EQ(lines[0].rfind("modbus test: sequence 0 axis 1", 0), 0u) << lines[0];
  EXPECT_EQ(lines[2].rfind("modbus test: sequence 2 axis 1", 0), 0u) << lines[2];
  // Within the same second: nothing more is printed, all counted.
  log.push(event(10, Status::kOutsideDomain));
  logger.drain(t0 + std::chrono::milliseconds(500));
  EXPECT_EQ(lines.size(), 3u);
  EXPECT_EQ(logger.suppressed(), 8u);
  // The next second: the summary of the last one, then new lines again.
  log.push(event(11, Status::kOutsideDomain));
  logger.drain(t0 + std::chrono::milliseconds(1200));
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_NE(lines[3].find("8 more refused or outside-domain answers"), std::string::npos)
      << lines[3];
  EXPECT_NE(lines[4].find("sequence 11"), std::string::npos) << lines[4];
  EXPECT_EQ(logger.events(), 12u);
  // A full ring: the events it dropped are reported, once.
  for (std::uint32_t k = 0; k < 70; ++k) log.push(event(100 + k, Status::kNoModel));
  EXPECT_EQ(log.dropped(), 6u);
  logger.finish(t0 + std::chrono::milliseconds(1300));
  bool reported = false;
  for (const auto& l : lines) {
    reported =
        reported || l.find("6 refused or outside-domain answers came faster") != std::string::npos;
  }
  EXPECT_TRUE(reported);
  EXPECT_EQ(logger.events(), 12u + 64u);
  EXPECT_NE(lines.back().find("more refused or outside-domain answers"), std::string::npos)
      << lines.back();
}

}  // namespace
}  // namespace cmmcomp::serving
