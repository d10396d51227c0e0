// SPDX-License-Identifier: MIT
/// @file The probing program and the evaluation of the length test.
#include <algorithm>
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/length_test.hpp>

namespace cmmcomp::vc {

void LengthProgram::validate() const {
  if (lengths_mm.empty()) throw ConfigError("no lengths to measure");
  if (y_mm.empty()) throw ConfigError("no carriage positions Y");
  for (double l : lengths_mm) {
    if (!(l > 0) || !std::isfinite(l)) throw ConfigError("lengths must be positive [mm]");
  }
  for (double y : y_mm) {
    if (!(y >= 0 && y <= 2000)) throw ConfigError("Y must be within 0 … 2000 mm");
  }
  if (repeats < 1) throw ConfigError("--repeats must be at least 1");
  if (!std::isfinite(x0_mm)) throw ConfigError("x0 must be finite");
  (void)time_per_point_s(fast, dwell_s, smoothing_s);
  (void)time_per_point_s(slow, dwell_s, smoothing_s);
  if (qualify) {
    qualification.validate();
    (void)time_per_point_s(qualification.map_setting, dwell_s, smoothing_s);
  }
}

compensation::MoveRequest request_for(const ProbeSetting& s, Face face, double y_mm) {
  compensation::MoveRequest m;
  m.axis = 0;  // X
  m.direction = {static_cast<double>(direction_of(face)), 0.0, 0.0};
  m.pv_mm_s = s.pv_mm_s;
  m.pa_mm_s2 = s.pa_mm_s2;
  m.pd_mm = s.pd_mm;
  m.av_mm_s = s.av_mm_s;
  m.aa_mm_s2 = s.aa_mm_s2;
  m.ad_mm = s.ad_mm;
  m.y_mm = y_mm;
  m.z_mm = 0.0;
  return m;
}

namespace {

/// Keeps the signed value of largest magnitude.
void keep_worst(double& worst, double e, bool first) {
  if (first || std::fabs(e) > std::fabs(worst)) worst = e;
}

}  // namespace

LengthTestResult run_length_test(const LengthProgram& program,
                                 TouchErrorModel& machine,
                                 const std::vector<CorrectionSource*>& agents,
                                 const std::function<void(std::size_t, std::size_t)>& progress) {
  program.validate();
  LengthTestResult result;
  for (const CorrectionSource* a : agents) {
    result.agent_labels.push_back(a->label());
    result.agent_places.push_back(a->where());
  }
  result.fast_time_per_point_s =
      time_per_point_s(program.fast, program.dwell_s, program.smoothing_s);
  result.slow_time_per_point_s =
      time_per_point_s(program.slow, program.dwell_s, program.smoothing_s);

  if (program.qualify) {
    result.qualification =
        qualify(program.qualification, program.y_mm, {program.slow, program.fast}, machine);
  }

  const std::size_t n_agents = agents.size();
  const std::size_t n_y = program.y_mm.size();
  const std::size_t n_l = program.lengths_mm.size();
  const std::size_t total = 2 * n_y * n_l * static_cast<std::size_t>(program.repeats) * 2;
  result.cases.resize(n_y * n_l);
  for (std::size_t iy = 0; iy < n_y; ++iy) {
    for (std::size_t il = 0; il < n_l; ++il) {
      CaseResult& c = result.cases[iy * n_l + il];
      c.y_mm = program.y_mm[iy];
      c.length_mm = program.lengths_mm[il];
      c.mpe_e_um = mpe_e_um(c.length_mm);
      c.fast_compensated_um.assign(n_agents, 0.0);
    }
  }

  std::uint64_t index = 0;
  const ProbeSetting* settings[2] = {&program.slow, &program.fast};
  for (const ProbeSetting* s : settings) {
    const bool fast = s == &program.fast;
    const double time_s = time_per_point_s(*s, program.dwell_s, program.smoothing_s);
    for (std::size_t iy = 0; iy < n_y; ++iy) {
      for (std::size_t il = 0; il < n_l; ++il) {
        CaseResult& c = result.cases[iy * n_l + il];
        for (int rep = 0; rep < program.repeats; ++rep) {
          PointRecord pts[2];
          const Face faces[2] = {Face::kB, Face::kA};
          for (int k = 0; k < 2; ++k) {
            PointRecord& p = pts[k];
            p.index = index++;
            p.setting = *s;
            p.length_mm = c.length_mm;
            p.y_mm = c.y_mm;
            p.repeat = rep;
            p.face = faces[k];
            p.true_mm = face_position_mm(p.face, program.x0_mm, p.length_mm);
            p.time_s = time_s;
            // The controller asks before the approach; then the machine probes.
            if (fast && s->compensated) {
              const compensation::MoveRequest req = request_for(*s, p.face, p.y_mm);
              for (CorrectionSource* a : agents) {
                AppliedAnswer aa;
                aa.answer = a->ask(req);
                p.answers.push_back(aa);
              }
            }
            p.rae_um = machine.rae_um(*s, p.y_mm, p.index);
            p.scale_mm = scale_point_mm(p.true_mm, direction_of(p.face), p.rae_um);
            p.qualified_mm = p.scale_mm;
            if (result.qualification) {
              p.qualified_mm = corrected_point_mm(
                  p.scale_mm, result.qualification->removed_um(*s, p.y_mm) * direction_of(p.face));
            }
            for (AppliedAnswer& aa : p.answers) {
              aa.corrected_mm = aa.answer.usable
                                    ? corrected_point_mm(p.scale_mm, aa.answer.correction_um[0])
                                    : p.scale_mm;
              if (!aa.answer.usable) ++result.unusable_answers;
            }
            if (progress) progress(static_cast<std::size_t>(index), total);
          }
          const PointRecord& b = pts[0];
          const PointRecord& a = pts[1];
          const bool first = rep == 0;
          const double e = length_error_um(a.qualified_mm, b.qualified_mm, c.length_mm);
          if (fast) {
            keep_worst(c.fast_uncompensated_um, e, first);
            for (std::size_t g = 0; g < a.answers.size(); ++g) {
              keep_worst(c.fast_compensated_um[g],
                         length_error_um(
                             a.answers[g].corrected_mm, b.answers[g].corrected_mm, c.length_mm),
                         first);
            }
          } else {
            keep_worst(c.slow_um, e, first);
          }
          result.points.push_back(b);
          result.points.push_back(a);
        }
      }
    }
  }

  for (std::size_t iy = 0; iy < n_y; ++iy) {
    YSummary y;
    y.y_mm = program.y_mm[iy];
    y.fast_compensated_max_um.assign(n_agents, 0.0);
    y.fast_compensated_pass.assign(n_agents, true);
    for (std::size_t il = 0; il < n_l; ++il) {
      const CaseResult& c = result.cases[iy * n_l + il];
      y.slow_max_um = std::max(y.slow_max_um, std::fabs(c.slow_um));
      y.slow_pass = y.slow_pass && std::fabs(c.slow_um) <= c.mpe_e_um;
      y.fast_uncompensated_max_um =
          std::max(y.fast_uncompensated_max_um, std::fabs(c.fast_uncompensated_um));
      y.fast_uncompensated_pass =
          y.fast_uncompensated_pass && std::fabs(c.fast_uncompensated_um) <= c.mpe_e_um;
      for (std::size_t g = 0; g < n_agents; ++g) {
        y.fast_compensated_max_um[g] =
            std::max(y.fast_compensated_max_um[g], std::fabs(c.fast_compensated_um[g]));
        y.fast_compensated_pass[g] =
            y.fast_compensated_pass[g] && std::fabs(c.fast_compensated_um[g]) <= c.mpe_e_um;
      }
    }
    result.per_y.push_back(y);
  }
  return result;
}

}  // namespace cmmcomp::vc
