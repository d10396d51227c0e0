// SPDX-License-Identifier: MIT
/// @file Hand-built compensator models with outputs known in closed form (tests only).
#pragma once

#include <array>
#include <cmmcomp/compensation/move_compensator.hpp>

namespace cmmcomp::test {

/// A 4-output paper network whose every rule has y_o = c_o + k_o·x̂_term, x̂ the normalised
/// input `term` − 1 (term 1 = PV, 2 = PD, …). Since the normalised firing strengths sum to 1, the
/// network output is exactly that wherever it is evaluated.
inline compensation::Model<PaperInputs> linear_model(const std::array<double, 4>& c,
                                                     const std::array<double, 4>& k,
                                                     int term = 1) {
  compensation::Model<PaperInputs> m;
  m.ranges = {fuzzy::InputRange{5.0, 80.0},
              fuzzy::InputRange{1.0, 50.0},
              fuzzy::InputRange{1.0, 10.0},
              fuzzy::InputRange{0.5, 5.0}};
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      m.params.centre(i, s) = 0.5 * s;
      m.params.width(i, s) = 0.4;
    }
  }
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < compensation::Model<PaperInputs>::kRules; ++j) {
      m.params.consequent(o, j, 0) = c[static_cast<unsigned>(o)];
      m.params.consequent(o, j, term) = k[static_cast<unsigned>(o)];
    }
  }
  return m;
}

/// The same for the 5-input model (PV, PD, AV, AD, Y; Y range [0, 500] mm): every rule has
/// y_o = c_o + k_o·x̂_term, term 5 = Y.
inline compensation::Model<CarriageInputs> linear_model_y(const std::array<double, 4>& c,
                                                          const std::array<double, 4>& k,
                                                          int term = 5) {
  compensation::Model<CarriageInputs> m;
  m.ranges = {fuzzy::InputRange{5.0, 80.0},
              fuzzy::InputRange{1.0, 50.0},
              fuzzy::InputRange{1.0, 10.0},
              fuzzy::InputRange{0.5, 5.0},
              fuzzy::InputRange{0.0, 500.0}};
  for (int i = 0; i < 5; ++i) {
    for (int s = 0; s < 3; ++s) {
      m.params.centre(i, s) = 0.5 * s;
      m.params.width(i, s) = 0.4;
    }
  }
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < compensation::Model<CarriageInputs>::kRules; ++j) {
      m.params.consequent(o, j, 0) = c[static_cast<unsigned>(o)];
      m.params.consequent(o, j, term) = k[static_cast<unsigned>(o)];
    }
  }
  return m;
}

}  // namespace cmmcomp::test
