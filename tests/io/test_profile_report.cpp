// SPDX-License-Identifier: MIT
/// @file Reports of a move profile.
#include <gtest/gtest.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/profile_report.hpp>
#include <sstream>
#include <stdexcept>
#include <string>

namespace cmmcomp::io {
namespace {

motion::MoveProfile baseline() {
  motion::MoveProfile p;
  EXPECT_EQ(motion::MoveProfile::plan(motion::baseline_move(), p), Status::kOk);
  return p;
}

TEST(ProfileReport, DescribesInstantsAndTouch) {
  const std::string s = describe_profile(baseline());
  EXPECT_NE(s.find("positioning acceleration end           0.200000"), std::string::npos) << s;
  EXPECT_NE(s.find("positioning deceleration start (RPE)   1.000000"), std::string::npos) << s;
  EXPECT_NE(s.find("approach start (after the dwell)       1.200000"), std::string::npos) << s;
  EXPECT_NE(s.find("touch (RAE)                            2.133333"), std::string::npos) << s;
  EXPECT_NE(s.find("touch at 50.000000 mm moving at 12.000000 mm/s"), std::string::npos) << s;
}

TEST(ProfileReport, CsvHasHeaderSamplesAndInstants) {
  const std::string csv = profile_csv(baseline(), 11);
  std::istringstream in(csv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "t_s,position_mm,velocity_mm_s,acceleration_mm_s2,jerk_mm_s3");
  int rows = 0;
  bool has_accel_end = false;
  bool has_decel_start = false;
  while (std::getline(in, line)) {
    ++rows;
    if (line.rfind("0.2,", 0) == 0) has_accel_end = true;
    if (line.rfind("1,", 0) == 0) has_decel_start = true;
  }
  // 11 even samples (0.21333 s apart) plus 0.2, 1.0, 1.2 (positioning end = approach start
  // without a dwell) and 1.4 (the touch is already a sample).
  EXPECT_EQ(rows, 15);
  EXPECT_TRUE(has_accel_end);
  EXPECT_TRUE(has_decel_start);
  EXPECT_THROW(profile_csv(baseline(), 1), cmmcomp::ConfigError);
}

}  // namespace
}  // namespace cmmcomp::io
