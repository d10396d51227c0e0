// SPDX-License-Identifier: MIT
/// @file Exceptions thrown by setup and offline code (never on the real-time path).
#pragma once

#include <stdexcept>
#include <string>

namespace cmmcomp {

/// Any failure of offline code: I/O, simulation, training. The message is meant for a user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A configuration, machine, model or data file that cannot be used. The message names the file
/// and, where known, the line, the column or key, and what is wrong.
class ConfigError : public Error {
 public:
  using Error::Error;
};

}  // namespace cmmcomp
