// SPDX-License-Identifier: MIT
/// @file The result docs/protocol-modbus.md's worked example must give, as GoogleTest checks.
#pragma once

#include <gtest/gtest.h>

#include <cmmcomp/plugins/modbus_register_map.hpp>

#include "modbus_example.hpp"

namespace cmmcomp::test {

/// The example request (sequence 7) answered by the example model: MPE 11, RPE −1.5, MAE 5,
/// RAE 2 µm, correction (1.2, 0, −1.6) µm as binary32, status ok.
inline void expect_example_result(const plugins::modbus::Result& r) {
  EXPECT_EQ(r.sequence, 7);
  EXPECT_EQ(r.status, 0);
  EXPECT_EQ(r.flags, compensation::kFlagOk);
  EXPECT_EQ(r.mpe_um, 11.0);
  EXPECT_EQ(r.rpe_um, -1.5);
  EXPECT_EQ(r.mae_um, 5.0);
  EXPECT_EQ(r.rae_um, 2.0);
  EXPECT_EQ(r.correction_um[0], static_cast<double>(1.2f));
  EXPECT_EQ(r.correction_um[1], 0.0);
  EXPECT_EQ(r.correction_um[2], static_cast<double>(-1.6f));
  EXPECT_EQ(r.model_id, kExampleModelId);
}

}  // namespace cmmcomp::test
