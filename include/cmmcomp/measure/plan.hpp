// SPDX-License-Identifier: MIT
/// @file The measurement plan: a designed experiment as the probing moves a CMM runs, in
/// randomised run order, with their coordinates (`cmmcomp-measure plan`, docs/measurement.md).
///
/// Each move probes one nominal point along one machine axis: it starts PD + AD away from the
/// point along the surface normal IJK, positions over PD at PV to the pre-hit point, then
/// approaches over AD at AV to the point (the touch). The same rows as `cmmcomp-sim dataset`
/// for the same design, levels and seed, so a twin dataset and a machine campaign line up.
/// Offline: allocates, throws ConfigError.
#pragma once

#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/dynamics/dataset.hpp>
#include <cmmcomp/schema.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::measure {

/// A point or a direction in machine coordinates [mm] (a direction is unitless).
struct Vec3 {
  double x = 0, y = 0, z = 0;
};

/// The coordinate of `p` along machine axis `axis` ('x', 'y' or 'z').
inline double axis_value(const Vec3& p, char axis) {
  return axis == 'x' ? p.x : axis == 'y' ? p.y : p.z;
}

/// How to plan an experiment.
struct PlanOptions {
  std::string design = "l18";                   ///< l18 | l9 | l27 | full | lhs
  std::string levels;                           ///< --levels text; empty = the paper's Table 3
  int repeats = 3;                              ///< repeats of every run (the paper: 3)
  int lhs_samples = 270;                        ///< runs of an lhs design
  std::uint64_t seed = 1;                       ///< run order (and lhs) seed
  dynamics::FixedSettings fixed{};              ///< PA, AA and, without Y levels, Y
  Vec3 nominal{0.0, paper::kBaseline.y_mm, 0};  ///< the probed point [mm]; y = each move's Y
  Vec3 normal{1.0, 0.0, 0.0};                   ///< surface normal IJK: ±X, ±Y or ±Z
  double search_mm = 2.0;   ///< I++ PtMeasPar.Search: how far past the point the probe searches
  double retract_mm = 1.0;  ///< I++ PtMeasPar.Retract: the back-off after the touch
};

/// One move of the plan.
struct PlannedMove {
  int move_id = 0;        ///< 1-based, in design order: (run − 1) · repeats + repeat
  int run_order = 0;      ///< 1-based position in the order the machine runs the moves
  int run = 0;            ///< 1-based run of the design
  int repeat = 0;         ///< 1-based repeat of that run
  DatasetRow settings{};  ///< PV, PD, AV, AD, PA, AA, Y (file units); errors zero
  char axis = 'x';        ///< the machine axis the move runs along
  int direction = -1;     ///< motion along that axis: −(the normal's sign)
  Vec3 start, prehit, touch;
  Vec3 normal;
};

/// Plans the experiment: the design's runs × repeats, ordered at random (seeded) in blocks, one
/// block per repeat holding every run once, so repeats of a run are spread over the session and
/// never back to back. Returned in run order. Throws ConfigError for bad options.
std::vector<PlannedMove> plan_experiment(const PlanOptions& options);

/// plan.csv (docs/measurement.md): one header row, then one row per move in run order.
std::string format_plan_csv(const std::vector<PlannedMove>& moves);
/// Parses plan.csv; errors name `source` and the line. The result is in run order.
std::vector<PlannedMove> parse_plan_csv(const std::string& text, const std::string& source);
std::vector<PlannedMove> read_plan_csv(const std::string& path);

/// The plan as an I++ DME command program (ISO 22093 text, numbered tags), one block per move:
/// GoTo the start, GoTo the pre-hit point at PV/PA (the positioning), PtMeas at AV/AA with
/// Approach = AD (docs/measurement.md, "The I++ program"). Throws ConfigError past tag 99999.
std::string format_ipp_program(const std::vector<PlannedMove>& moves, const PlanOptions& options);

/// What an I++ program commands for one PtMeas, as read back from the program text.
struct IppPoint {
  double goto_speed = 0, goto_accel = 0;  ///< GoToPar at the last GoTo before the PtMeas
  double meas_speed = 0, meas_accel = 0, approach = 0, search = 0, retract = 0;
  std::vector<Vec3> gotos;  ///< every GoTo since the previous PtMeas, in order
  Vec3 point, ijk;
};

/// Reads an I++ program back (the subset format_ipp_program writes: StartSession, SetProp of
/// Tool.GoToPar.* and Tool.PtMeasPar.*, GoTo, PtMeas, EndSession); checks the tags increase.
/// Throws ConfigError "source:line: ..." for anything else.
std::vector<IppPoint> parse_ipp_program(const std::string& text, const std::string& source);

}  // namespace cmmcomp::measure
