// SPDX-License-Identifier: MIT
/// @file Describes a struct of named physical parameters once, for files, docs and identification.
///
/// A machine file, its documentation, its validation and the identification tool all iterate the
/// same table, so a parameter is declared in exactly one place.
#pragma once

namespace cmmcomp::dynamics {

/// One physical parameter of a model struct `Params`.
template <typename Params>
struct ParameterInfo {
  const char* section;      ///< TOML table, e.g. "bridge"
  const char* key;          ///< key with its unit, e.g. "yaw_stiffness_Nm_per_rad"
  const char* description;  ///< one sentence for docs and messages
  double& (*ref)(Params&);  ///< the value it names inside a Params
  double min;               ///< smallest value a file may hold (inclusive): physical at all
  double max;               ///< largest value a file may hold (inclusive)
  bool identifiable;        ///< fitted by `cmmcomp-sim identify` by default
  double plausible_min;     ///< smallest plausible value on a real machine (identification bound)
  double plausible_max;     ///< largest plausible value (identification bound)
  const char* basis;        ///< where the plausible range comes from (one sentence, for the docs)
  /// The first file format that has the key; an older file does not, and reads `absent`.
  int since_format = 0;
  double absent = 0.0;  ///< the value an older file's machine has (the mechanism switched off)

  double get(const Params& p) const { return ref(const_cast<Params&>(p)); }
  void set(Params& p, double value) const { ref(p) = value; }
};

}  // namespace cmmcomp::dynamics
