// SPDX-License-Identifier: MIT
/// @file The qualified reference: what an uncompensated CMM removes from a touch before it
/// reports a point, a static reversal map over the carriage position and the probe qualified on a
/// reference sphere (docs/planner.md, "The qualified reference"). The virtual controller measures
/// it (cmmcomp/vc/qualification.hpp); the planner judges an uncompensated setting by what
/// it leaves.
///
/// Why: a touch lags by a quasi-static part (on the twin the hose's Coulomb drag: 3.6–7 µm per
/// touch against the motion at any speed) plus a part the setting adds. A real CMM's error map
/// (CAA) holds the axis's bidirectional reversal along the carriage position, measured slowly,
/// and qualifying the probe at the measuring setting absorbs the rest of the lag at the
/// sphere's Y into the effective stylus radius. What remains of a touch of a setting at Y is
///
///     residual(Y) = (RAE(Y) − RAE(Y_sphere)) − (map(Y) − map(Y_sphere))
///
/// how the setting's lag beyond the quasi-static one changes from the sphere's Y to Y.
#pragma once

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <string>
#include <vector>

namespace cmmcomp::planning {

struct QualifiedReference {
  double sphere_y_mm = 250.0;    ///< carriage position of the reference sphere [mm]
  std::vector<double> map_y_mm;  ///< the reversal map's nodes [mm], strictly ascending
  std::vector<double> map_um;    ///< the quasi-static touch lag (RAE) at each node [µm]

  /// Throws ConfigError when the map is empty, its lists differ in length, a value is not
  /// finite or the nodes do not ascend strictly.
  void validate() const {
    if (!std::isfinite(sphere_y_mm)) throw ConfigError("the reference sphere's Y is not finite");
    if (map_y_mm.empty() || map_y_mm.size() != map_um.size()) {
      throw ConfigError("the reversal map needs one lag per node and at least one node");
    }
    for (std::size_t i = 0; i < map_y_mm.size(); ++i) {
      if (!std::isfinite(map_y_mm[i]) || !std::isfinite(map_um[i])) {
        throw ConfigError("the reversal map holds a value that is not finite");
      }
      if (i > 0 && !(map_y_mm[i] > map_y_mm[i - 1])) {
        throw ConfigError("the reversal map's Y must ascend strictly");
      }
    }
  }

  /// The map at `y_mm` [µm]: linear between nodes, the end node's value beyond them; 0 for an
  /// empty map.
  double map_at_um(double y_mm) const noexcept {
    if (map_y_mm.empty() || map_um.size() != map_y_mm.size()) return 0.0;
    if (!(y_mm > map_y_mm.front())) return map_um.front();
    if (!(y_mm < map_y_mm.back())) return map_um.back();
    std::size_t k = 1;
    while (map_y_mm[k] < y_mm) ++k;  // bounded: y_mm < the last node
    const double u = (y_mm - map_y_mm[k - 1]) / (map_y_mm[k] - map_y_mm[k - 1]);
    return map_um[k - 1] + u * (map_um[k] - map_um[k - 1]);
  }

  /// What the map and the qualification leave of a touch that lags by `rae_um` at `y_mm`, when
  /// the same setting lags by `rae_at_sphere_um` at the sphere [µm] (the file comment).
  double residual_um(double rae_um, double y_mm, double rae_at_sphere_um) const noexcept {
    return (rae_um - rae_at_sphere_um) - (map_at_um(y_mm) - map_at_um(sphere_y_mm));
  }
};

}  // namespace cmmcomp::planning
