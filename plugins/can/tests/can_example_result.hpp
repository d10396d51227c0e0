// SPDX-License-Identifier: MIT
/// @file The correction docs/protocol-can.md's worked example must give, as GoogleTest checks.
#pragma once

#include <gtest/gtest.h>

#include <cmmcomp/plugins/can_protocol.hpp>

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

}  // namespace cmmcomp::test
