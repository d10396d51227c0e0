// SPDX-License-Identifier: MIT
/// @file Probe qualification and a static reversal map: what a CMM's controller removes from an
/// uncompensated touch before it reports a point (tools/cmmcomp-vc/README.md, "Qualified
/// reference").
///
/// Why: on the twin, as in the paper's Table 2, a touch lags by 3.6–7 µm even at the slowest
/// setting. That is a quasi-static deflection under the hose's Coulomb drag, against the motion,
/// and a real CMM does not leave it in its results:
///  - its error map (CAA) holds each axis's bidirectional reversal along the carriage position,
///    measured quasi-statically (ISO 230-2's reversal value, position by position);
///  - its probe is qualified on a reference sphere at the setting it measures with, and the
///    effective tip radius absorbs the part of the touch's lag that the map leaves.
/// Together they remove the static deflection everywhere and the setting's whole lag at the
/// sphere's Y. What remains of an uncompensated touch is how the setting's dynamic lag changes
/// with Y, plus the probing scatter.
///
/// Only the uncompensated columns are qualified. The model predicts the whole lag, static part
/// included, so a map on top of its correction would remove that part twice; and qualifying the
/// compensated columns would remove the model's error at the sphere's Y (at another Y what
/// remains is err(Y) − err(Y_sphere), which can be larger or smaller), so they keep the plain
/// correction.
#pragma once

#include <cmmcomp/planning/qualified_reference.hpp>
#include <cmmcomp/vc/probe_setting.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <cstdint>
#include <vector>

namespace cmmcomp::vc {

/// How to qualify: where the sphere is, how many touches each measurement averages, and the
/// quasi-static setting of the reversal map.
struct QualificationPlan {
  double sphere_y_mm = 250;  ///< carriage position of the reference sphere [mm]
  int touches = 10;          ///< touches averaged for each map node and each qualification
  /// The reversal map's quasi-static setting: the vc's slow reference (PV 20, AV 1 over 2 mm),
  /// also when the length test's reference is another setting.
  ProbeSetting map_setting = default_slow_setting();

  /// Throws ConfigError when the sphere is outside 0 … 2000 mm or touches < 1.
  void validate() const;
};

/// The first noise index of the qualification's touches: far above any program's points, so
/// the qualification never reuses a point's noise.
inline constexpr std::uint64_t kQualificationIndex0 = std::uint64_t{1} << 40;

/// What the qualification measured.
struct Qualification {
  QualificationPlan plan;
  /// The sphere's Y and the map: nodes at the program's Y and the sphere's, ascending, each the
  /// mean RAE at the map setting [µm]. What cmmcomp-plan --reversal-map takes.
  planning::QualifiedReference reference;
  std::vector<ProbeSetting> settings;  ///< the qualified settings
  std::vector<double> offsets_um;      ///< per setting: mean RAE at the sphere − map there [µm]
  std::uint64_t touches_used = 0;      ///< touches the map and the qualifications took

  /// The qualification offset of `s` [µm]. Throws Error when `s` was not qualified.
  double offset_um(const ProbeSetting& s) const;
  /// The lag the controller removes from an uncompensated touch of `s` at `y_mm` [µm]:
  /// map(y) + offset(s). The qualified point is scale + removed·d (length_geometry.hpp), and
  /// what remains of the touch is QualifiedReference::residual_um.
  double removed_um(const ProbeSetting& s, double y_mm) const {
    return reference.map_at_um(y_mm) + offset_um(s);
  }
};

/// Measures the map at every Y of `y_mm` and at the sphere (plan.touches touches each, at
/// plan.map_setting), then qualifies each of `settings` at the sphere (plan.touches touches
/// each). Noise indices run from kQualificationIndex0. Throws ConfigError for a bad plan.
Qualification qualify(const QualificationPlan& plan,
                      const std::vector<double>& y_mm,
                      const std::vector<ProbeSetting>& settings,
                      TouchErrorModel& machine);

}  // namespace cmmcomp::vc
