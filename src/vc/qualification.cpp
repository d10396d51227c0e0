// SPDX-License-Identifier: MIT
/// @file Probe qualification and the static reversal map (qualification.hpp).
#include <algorithm>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/qualification.hpp>

namespace cmmcomp::vc {

namespace {

bool same_setting(const ProbeSetting& a, const ProbeSetting& b) {
  return a.pv_mm_s == b.pv_mm_s && a.pa_mm_s2 == b.pa_mm_s2 && a.pd_mm == b.pd_mm &&
         a.av_mm_s == b.av_mm_s && a.aa_mm_s2 == b.aa_mm_s2 && a.ad_mm == b.ad_mm;
}

}  // namespace

void QualificationPlan::validate() const {
  if (!(sphere_y_mm >= 0 && sphere_y_mm <= 2000)) {
    throw ConfigError("the reference sphere's Y must be within 0 … 2000 mm");
  }
  if (touches < 1) throw ConfigError("qualification needs at least 1 touch");
}

double Qualification::offset_um(const ProbeSetting& s) const {
  for (std::size_t i = 0; i < settings.size(); ++i) {
    if (same_setting(settings[i], s)) return offsets_um[i];
  }
  throw Error("the setting '" + s.name + "' was not qualified");
}

Qualification qualify(const QualificationPlan& plan,
                      const std::vector<double>& y_mm,
                      const std::vector<ProbeSetting>& settings,
                      TouchErrorModel& machine) {
  plan.validate();
  Qualification q;
  q.plan = plan;
  std::uint64_t index = kQualificationIndex0;
  const auto mean_rae = [&](const ProbeSetting& s, double y) {
    double sum = 0;
    for (int k = 0; k < plan.touches; ++k) sum += machine.rae_um(s, y, index++);
    return sum / plan.touches;
  };
  // The map's nodes: every Y of the program and the sphere's, each once, ascending.
  planning::QualifiedReference& ref = q.reference;
  ref.sphere_y_mm = plan.sphere_y_mm;
  ref.map_y_mm = y_mm;
  ref.map_y_mm.push_back(plan.sphere_y_mm);
  std::sort(ref.map_y_mm.begin(), ref.map_y_mm.end());
  ref.map_y_mm.erase(std::unique(ref.map_y_mm.begin(), ref.map_y_mm.end()), ref.map_y_mm.end());
  for (double y : ref.map_y_mm) ref.map_um.push_back(mean_rae(plan.map_setting, y));
  const double map_at_sphere = ref.map_at_um(plan.sphere_y_mm);
  for (const ProbeSetting& s : settings) {
    q.settings.push_back(s);
    q.offsets_um.push_back(mean_rae(s, plan.sphere_y_mm) - map_at_sphere);
  }
  q.touches_used = index - kQualificationIndex0;
  return q;
}

}  // namespace cmmcomp::vc
