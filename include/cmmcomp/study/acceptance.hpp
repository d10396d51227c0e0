// SPDX-License-Identifier: MIT
/// @file Acceptance as code: a measured figure against its limit, and one check over a list of
/// them with one list of known-unmet targets.
///
/// Contract: a Target is met when `measured` lies on the right side of `limit` (kAtLeast: ≥,
/// kAtMost: ≤). check() passes when every target is met, except those named in the known-unmet
/// list, which must be STILL unmet: a listed target that is now met fails too, so the list
/// cannot outlive its reason. Limits are built from the paper's constants (paper_reference.hpp)
/// and the noise σ, never retyped (table5_targets). The list format is one target name per line;
/// blank lines and lines starting with `#` are skipped. Setup-time code (allocates, throws
/// ConfigError for an unreadable list).
#pragma once

#include <array>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/training/evaluation.hpp>
#include <set>
#include <string>
#include <vector>

namespace cmmcomp::study {

/// One measured figure against its limit.
struct Target {
  enum class Kind { kAtLeast, kAtMost };
  std::string name;  ///< unique in its check, as the known-unmet list names it
  double measured = 0;
  double limit = 0;
  Kind kind = Kind::kAtMost;
  std::string unit;          ///< for the report ("%", "um")
  bool known_unmet = false;  ///< set by check() from the list
  bool met() const { return kind == Kind::kAtLeast ? measured >= limit : measured <= limit; }
};

/// The names of the targets known to be unmet (see the file comment for the format).
using KnownUnmet = std::set<std::string>;
KnownUnmet parse_known_unmet(const std::string& text);
/// Reads a list file; ConfigError when it cannot be read.
KnownUnmet read_known_unmet(const std::string& path);

/// What check() found: every failure as one line (a target missed, or listed and now met).
struct Verdict {
  bool passed = true;
  std::vector<std::string> failures;
};

/// Marks the listed targets and judges them all (file comment). A name in `known` that no
/// target carries is a failure too ("not measured": a stale list).
Verdict check(std::vector<Target>& targets, const KnownUnmet& known);

/// The mean |noise| of a parameter whose noise is normal with Table 1's σ: √(2/π)·σ [µm]. A
/// model's mean residual cannot go below it on noisy test data.
double noise_floor_um(std::size_t parameter);

/// The accuracy targets of a Table 5 (names `PREFIX<param>_reduction` and
/// `PREFIX<param>_residual`, param = mpe, rpe, mae, rae): the reduction at least the paper's
/// Table 5 (when `check_reduction`), and the mean residual at most `residual_factor` × the noise
/// floor (noise_floor_um).
std::vector<Target> table5_targets(const std::string& prefix,
                                   const std::array<training::Table5Row, kErrorCount>& table,
                                   bool check_reduction,
                                   double residual_factor = 1.5);

}  // namespace cmmcomp::study
