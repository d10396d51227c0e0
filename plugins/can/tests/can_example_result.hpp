// SPDX-License-Identifier: MIT
/// @file The correction docs/protocol-can.md's worked example must give, as GoogleTest checks.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstddef>

#include "can_test_frames.hpp"

namespace cmmcomp::test {

/// The example move (sequence 5) answered by the example model: MPE 3.5, RPE −1, MAE 4,
/// RAE 3.5 µm, correction x −3.5 µm, flags OK, model id 0xC0FFEE01.
inline void expect_example_response(const plugins::can::DecodedResponse& d) {
  EXPECT_DOUBLE_EQ(d.correction.mpe_um, 3.5);
  EXPECT_DOUBLE_EQ(d.correction.rpe_um, -1.0);
  EXPECT_DOUBLE_EQ(d.correction.mae_um, 4.0);
  EXPECT_DOUBLE_EQ(d.correction.rae_um, 3.5);
  EXPECT_DOUBLE_EQ(d.correction.correction_um[0], -3.5);
  EXPECT_EQ(d.correction.flags, compensation::kFlagOk);
  EXPECT_EQ(d.correction.model_id, kExampleModelId);
  EXPECT_EQ(d.correction.sequence, 5u);
}

/// The second example (sequence 6, WantInterval) with the example's calibration: the same
/// result, and part 3 with U95 2.74, 2.16, 1.3, 0.68 µm and no interval flag.
inline void expect_example_interval_response(const plugins::can::DecodedResponse& d) {
  EXPECT_DOUBLE_EQ(d.correction.mpe_um, 3.5);
  EXPECT_DOUBLE_EQ(d.correction.rae_um, 3.5);
  EXPECT_DOUBLE_EQ(d.correction.correction_um[0], -3.5);
  EXPECT_EQ(d.correction.flags, compensation::kFlagOk);
  EXPECT_EQ(d.correction.model_id, kExampleModelId);
  EXPECT_EQ(d.correction.sequence, 6u);
  EXPECT_TRUE(d.has_interval);
  EXPECT_EQ(d.interval_flags, 0);
  const std::array<double, 4> u95{2.74, 2.16, 1.3, 0.68};
  for (std::size_t k = 0; k < 4; ++k) EXPECT_NEAR(d.correction.u95_um[k], u95[k], 1e-12) << k;
}

}  // namespace cmmcomp::test
