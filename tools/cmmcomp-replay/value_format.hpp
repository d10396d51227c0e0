// SPDX-License-Identifier: MIT
/// @file Number formatting shared by the Modbus and CAN decoders.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>

namespace cmmcomp::replay {

/// `v` with `digits` significant digits ("%.*g").
inline std::string format_number(double v, int digits = 6) {
  char buf[48];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

/// `v` as `digits` lower-case hex digits.
inline std::string format_hex(std::uint64_t v, int digits) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "%0*llx", digits, static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace cmmcomp::replay
