// SPDX-License-Identifier: MIT
/// @file Exceptions thrown by setup and offline code (never on the real-time path).
///
/// Every failure a user can cause (a bad file, option, argument or data set) is a ConfigError;
/// other failures of offline work (a write, a solver) are an Error. Only a programming error,
/// an index out of range, is the standard library's std::out_of_range (as std::vector::at).
#pragma once

#include <stdexcept>
#include <string>

namespace cmmcomp {

/// Any failure of offline code: I/O, simulation, training. The message is meant for a user.
class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// A configuration, machine, model or data file, an option or an argument that cannot be used.
/// The message names the file and, where known, the line, the column or key, and what is wrong.
class ConfigError : public Error {
 public:
  using Error::Error;
};

}  // namespace cmmcomp
