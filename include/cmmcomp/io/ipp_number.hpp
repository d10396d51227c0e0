// SPDX-License-Identifier: MIT
/// @file How a number is written in an I++ DME (ISO 22093) command: fixed point, at most 16
/// characters, the resolution kIppResolutionMm (1e-6 mm, 1 nm), no exponent, no trailing zeros.
///
/// I++ DME parsers accept at most 16 characters per number; the shortest exact text of a double
/// (`5.700000000000003`) can take 17–24. A value is rounded to 6 decimals, and to fewer when its
/// sign and integer part need the room (from 1e9, or -1e8); one whose sign and integer part alone
/// need more than 16 characters (from 1e16, or -1e15) has no I++ form and is a ConfigError, as is
/// NaN or infinity.
#pragma once

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cstdio>
#include <string>

namespace cmmcomp::io {

/// The most characters an I++ DME number may have.
inline constexpr std::size_t kIppMaxNumberChars = 16;
/// The resolution of every number the project writes to I++ DME, in its unit (mm, mm/s, mm/s²).
inline constexpr double kIppResolutionMm = 1e-6;

/// `v` as I++ DME number text (above); `what` names the value in the error.
inline std::string format_ipp_number(double v, const char* what = "value") {
  if (!std::isfinite(v)) {
    throw ConfigError(std::string("I++ DME: the ") + what + " is not a finite number");
  }
  char buffer[64];
  for (int decimals = 6; decimals >= 0; --decimals) {
    const int n = std::snprintf(buffer, sizeof buffer, "%.*f", decimals, v);
    if (n <= 0 || static_cast<std::size_t>(n) >= sizeof buffer) continue;
    std::string s(buffer, static_cast<std::size_t>(n));
    if (s.find('.') != std::string::npos) {
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
    }
    if (s == "-0") s = "0";
    if (s.size() <= kIppMaxNumberChars) return s;
  }
  throw ConfigError(std::string("I++ DME: the ") + what + " " + std::to_string(v) +
                    " needs more than 16 characters");
}

}  // namespace cmmcomp::io
