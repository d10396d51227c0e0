// SPDX-License-Identifier: MIT
/// @file The model and the request of docs/protocol-modbus.md's worked example. No exceptions,
/// no libmodbus: included by the -fno-exceptions test as well as by modbus_test_support.hpp.
#pragma once

#include <cstdint>

#include "support/compensation_models.hpp"

namespace cmmcomp::test {

/// Model id the example publishes on axis 0.
inline constexpr std::uint64_t kExampleModelId = 0x0123456789ABCDEFull;

/// MPE = 10 + 2·x̂, RPE = −2 + x̂, MAE = 4 + 2·x̂, RAE = 1.5 + x̂ with x̂ = (PV − 5)/75.
inline compensation::Model<PaperInputs> example_model() {
  return linear_model({10.0, -2.0, 4.0, 1.5}, {2.0, 1.0, 2.0, 1.0});
}

/// PV 42.5 (x̂ = 0.5) → MPE 11, RPE −1.5, MAE 5, RAE 2; d = (0.6, 0, −0.8) → (1.2, 0, −1.6) µm.
inline compensation::MoveRequest example_request() {
  compensation::MoveRequest m;
  m.sequence = 7;
  m.axis = 0;
  m.direction = {0.6, 0.0, -0.8};
  m.pv_mm_s = 42.5;
  m.pa_mm_s2 = 200.0;
  m.pd_mm = 20.0;
  m.av_mm_s = 5.0;
  m.aa_mm_s2 = 50.0;
  m.ad_mm = 2.0;
  m.y_mm = 250.0;
  m.z_mm = -100.0;
  return m;
}

}  // namespace cmmcomp::test
