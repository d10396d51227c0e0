// SPDX-License-Identifier: MIT
/// @file Helpers shared by the CAN plugin's tests: the closed-form model and move of the
/// protocol document's worked example, and frames written as candump text.
#pragma once

#include <cctype>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstdint>
#include <cstdio>
#include <string>

#include "support/compensation_models.hpp"

namespace cmmcomp::test {

/// The model of docs/protocol-can.md's example: MPE = 3 + x̂, RPE = −1.25 + 0.5·x̂, MAE = 4,
/// RAE = 2.5 + 2·x̂ [µm] with x̂ = (PV − 5)/75 (tests/support/compensation_models.hpp).
inline compensation::Model<PaperInputs> example_model() {
  return linear_model({3.0, -1.25, 4.0, 2.5}, {1.0, 0.5, 0.0, 2.0});
}
inline constexpr std::uint64_t kExampleModelId = 0xC0FFEE01u;

/// The interval calibration of docs/protocol-can.md's second example (WantInterval): 95 %
/// coverage, in-domain half-widths 2.74, 2.16, 1.3, 0.68 µm for MPE, RPE, MAE, RAE (the example
/// move is inside the model's ranges, so these are its U95), gain 0.5 per range outside.
inline compensation::IntervalCalibration example_interval() {
  compensation::IntervalCalibration cal;
  cal.coverage = 0.95;
  cal.half_width = {2.74, 2.16, 1.3, 0.68};
  cal.extrapolation_gain = {0.5, 0.5, 0.5, 0.5};
  return cal;
}

/// Publishes the example model with its interval calibration on axis 0 of `comp`, model id
/// kExampleModelId (the first example's answers do not depend on the calibration).
inline Status publish_example(compensation::MoveCompensator& comp) {
  return comp.publish(0, example_model(), example_interval(), kExampleModelId);
}

/// The example's move: PV 42.5 mm/s (x̂ = 0.5), approach in −x, sequence 5.
inline compensation::MoveRequest example_move() {
  compensation::MoveRequest m;
  m.sequence = 5;
  m.axis = 0;
  m.direction = {-1.0, 0.0, 0.0};
  m.pv_mm_s = 42.5;
  m.pd_mm = 40.0;
  m.av_mm_s = 8.0;
  m.ad_mm = 2.0;
  m.pa_mm_s2 = 200.0;
  m.aa_mm_s2 = 60.0;
  m.y_mm = 250.0;
  m.z_mm = -100.0;
  return m;
}

/// The second example's move: the first one, sequence 6 (sent with WantInterval).
inline compensation::MoveRequest example_interval_move() {
  compensation::MoveRequest m = example_move();
  m.sequence = 6;
  return m;
}

/// `f` as cansend/candump write it: "301#14015E019CFF9001".
inline std::string to_text(const plugins::can::Frame& f) {
  char head[8];
  std::snprintf(head, sizeof head, "%03X#", static_cast<unsigned>(f.id));
  std::string s = head;
  for (std::size_t i = 0; i < f.dlc; ++i) {
    char byte[3];
    std::snprintf(byte, sizeof byte, "%02X", static_cast<unsigned>(f.data[i]));
    s += byte;
  }
  return s;
}

/// Parses "ID#HEX" (cansend syntax, classic frames); false when it is not one.
inline bool from_text(const std::string& text, plugins::can::Frame& f) {
  const std::size_t hash = text.find('#');
  if (hash == std::string::npos || hash == 0 || hash > 3) return false;
  const std::string hex = text.substr(hash + 1);
  if (hex.size() % 2 != 0 || hex.size() > 16) return false;
  for (char c : text.substr(0, hash) + hex) {
    if (std::isxdigit(static_cast<unsigned char>(c)) == 0) return false;
  }
  f = plugins::can::Frame{};
  f.id = static_cast<std::uint32_t>(std::stoul(text.substr(0, hash), nullptr, 16));
  f.dlc = static_cast<std::uint8_t>(hex.size() / 2);
  for (std::size_t i = 0; i < f.dlc; ++i) {
    f.data[i] = static_cast<std::uint8_t>(std::stoul(hex.substr(2 * i, 2), nullptr, 16));
  }
  return true;
}

}  // namespace cmmcomp::test
