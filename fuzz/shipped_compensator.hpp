// SPDX-License-Identifier: MIT
/// @file The compensator the protocol fuzz targets serve: the shipped model on axes 0..2 (axis 3
/// has none, so "no model" is reachable), built once per process.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cstdlib>

namespace cmmcomp::fuzzing {

inline const compensation::MoveCompensator& shipped_compensator() {
  // Never destroyed: libFuzzer may exit from any input, and the reachable object is no leak.
  static const compensation::MoveCompensator* const c = [] {
    auto* m = new compensation::MoveCompensator;
    const auto file = io::default_model_file();
    for (int axis = 0; axis < 3; ++axis) {
      if (m->publish(axis, file.compensation_model(), 1) != Status::kOk) std::abort();
    }
    return m;
  }();
  return *c;
}

}  // namespace cmmcomp::fuzzing
