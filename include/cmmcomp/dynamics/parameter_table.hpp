// SPDX-License-Identifier: MIT
/// @file Describes a struct of named physical parameters once, for files, docs and identification.
///
/// A machine file, its documentation, its validation and the identification tool all iterate the
/// same table, so a parameter is declared in exactly one place.
#pragma once

#include <cstddef>

namespace cmmcomp::dynamics {

/// One physical parameter of a model struct `Params` (a double member).
template <typename Params>
struct ParameterInfo {
  const char* section;      ///< TOML table, e.g. "yaw"
  const char* key;          ///< key with its unit, e.g. "stiffness_Nm_per_rad"
  const char* description;  ///< one sentence for docs and messages
  double Params::*field;    ///< the member it sets
  double min;               ///< smallest physical value (inclusive)
  double max;               ///< largest physical value (inclusive)
  bool identifiable;        ///< fitted by `cmmcomp-sim identify` (else held fixed)
};

}  // namespace cmmcomp::dynamics
