// SPDX-License-Identifier: MIT
/// @file Compiled with -fno-exceptions -fno-rtti: the compensator's RT path needs neither.
/// Exits 0 when a small model gives the expected correction.
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cstdio>

int main() {
  namespace cm = cmmcomp::compensation;
  cm::MoveCompensator comp;
  cm::Model<cmmcomp::PaperInputs> model;
  for (auto& r : model.ranges) r = cmmcomp::fuzzy::InputRange{0.5, 100.0};
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) {
      model.params.centre(i, s) = 0.5 * s;
      model.params.width(i, s) = 0.4;
    }
  }
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < cm::Model<cmmcomp::PaperInputs>::kRules; ++j) {
      model.params.consequent(o, j, 0) = o + 1.0;  // RAE = 4 µm everywhere
    }
  }
  if (comp.publish(1, model, 5u) != cmmcomp::Status::kOk) return 1;
  cm::MoveRequest r;
  r.axis = 1;
  r.direction = {0.0, -1.0, 0.0};
  r.pv_mm_s = r.pa_mm_s2 = r.pd_mm = r.av_mm_s = r.aa_mm_s2 = r.ad_mm = 10.0;
  cm::Correction out;
  if (comp.before_approach(r, out) != cmmcomp::Status::kOk) return 2;
  const double err = out.correction_um[1] + 4.0;
  if (err > 1e-12 || err < -1e-12 || out.model_id != 5u) return 3;
  r.ad_mm = -1.0;
  if (comp.before_approach(r, out) != cmmcomp::Status::kInvalidInput) return 4;
  std::puts("compensator_no_exceptions: ok");
  return 0;
}
