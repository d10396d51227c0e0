// SPDX-License-Identifier: MIT
/// @file The length test at speed: runs the probing program and evaluates the length errors.
#pragma once

#include <cmmcomp/vc/correction_source.hpp>
#include <cmmcomp/vc/length_geometry.hpp>
#include <cmmcomp/vc/probe_setting.hpp>
#include <cmmcomp/vc/qualification.hpp>
#include <cmmcomp/vc/twin_probe.hpp>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace cmmcomp::vc {

/// What to measure.
struct LengthProgram {
  std::vector<double> lengths_mm{20, 50, 100, 200, 400};  ///< nominal lengths of the step gauge
  std::vector<double> y_mm{0, 250, 500};                  ///< carriage positions
  double x0_mm = 100;  ///< X of face B of every length (the gauge's first face)
  int repeats = 3;     ///< measurements of each length per case (as ISO 10360-2)
  ProbeSetting fast = default_fast_setting();  ///< compensated setting
  ProbeSetting slow = default_slow_setting();  ///< uncompensated reference setting
  /// The machine controller's settings that shape every move (the machine file's [controller]):
  /// they count in the time per point.
  double dwell_s = 0.0;
  double smoothing_s = 0.0;
  /// Qualify the uncompensated columns (qualification.hpp): a static reversal map and the probe
  /// qualified at the slow and at the fast setting. Off: the raw scale points.
  bool qualify = false;
  QualificationPlan qualification;

  /// Throws ConfigError when a list is empty, a length is not positive, repeats < 1, or a setting
  /// cannot be planned.
  void validate() const;
};

/// One agent's answer for one point, applied.
struct AppliedAnswer {
  Answer answer;            ///< as received
  double corrected_mm = 0;  ///< scale point + correction (the scale point when not usable)
};

/// One probed point.
struct PointRecord {
  std::uint64_t index = 0;  ///< program order; the twin's noise stream
  ProbeSetting setting;     ///< the setting it was probed with
  double length_mm = 0;
  double y_mm = 0;
  int repeat = 0;  ///< 0-based
  Face face = Face::kA;
  double true_mm = 0;   ///< where the face is
  double rae_um = 0;    ///< the twin's RAE of this touch (with noise)
  double scale_mm = 0;  ///< what the scale reported
  /// The scale point less the lag the qualification removes (scale_mm when not qualified):
  /// what an uncompensated controller reports.
  double qualified_mm = 0;
  double time_s = 0;                   ///< time per point of the setting
  std::vector<AppliedAnswer> answers;  ///< one per agent, empty for the reference setting
};

/// The length errors of one case (setting × Y × length): the worst repeat, i.e. the signed error
/// of largest magnitude.
struct CaseResult {
  double y_mm = 0;
  double length_mm = 0;
  double mpe_e_um = 0;
  double slow_um = 0;                       ///< slow reference, uncompensated
  double fast_uncompensated_um = 0;         ///< fast setting, scale points as reported
  std::vector<double> fast_compensated_um;  ///< fast setting, per agent
};

/// Per Y: the largest |E| over the lengths and whether every length met MPE_E.
struct YSummary {
  double y_mm = 0;
  double slow_max_um = 0;
  bool slow_pass = true;
  double fast_uncompensated_max_um = 0;
  bool fast_uncompensated_pass = true;
  std::vector<double> fast_compensated_max_um;  ///< per agent
  std::vector<bool> fast_compensated_pass;      ///< per agent
};

/// Everything the test produced.
struct LengthTestResult {
  std::vector<std::string> agent_labels;
  std::vector<std::string> agent_places;
  std::vector<PointRecord> points;
  std::vector<CaseResult> cases;  ///< by Y, then length
  std::vector<YSummary> per_y;
  double fast_time_per_point_s = 0;
  double slow_time_per_point_s = 0;
  std::uint64_t unusable_answers = 0;          ///< answers that could not be applied
  std::optional<Qualification> qualification;  ///< measured before the program when asked for
};

/// Runs `program`: the qualification first when asked for, then for each setting (slow, then
/// fast), Y, length, repeat: face B, then face A.
/// Before each fast approach every agent is asked (in order) for the correction; then the touch
/// is measured by `machine`. `progress` (optional) is called after each point.
/// Throws Error when an agent fails on the transport.
LengthTestResult run_length_test(
    const LengthProgram& program,
    TouchErrorModel& machine,
    const std::vector<CorrectionSource*>& agents,
    const std::function<void(std::size_t, std::size_t)>& progress = {});

/// The request a controller sends for a point (sequence 0: the source numbers it).
compensation::MoveRequest request_for(const ProbeSetting& s, Face face, double y_mm);

}  // namespace cmmcomp::vc
