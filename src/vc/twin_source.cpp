// SPDX-License-Identifier: MIT
/// @file The machine as a correction source (twin_source.hpp).
#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/twin_source.hpp>
#include <utility>

namespace cmmcomp::vc {

TwinSource::TwinSource(std::string label, const dynamics::Machine& machine)
    : label_(std::move(label)), where_("twin " + machine.name), simulator_(machine) {}

Answer TwinSource::ask(const compensation::MoveRequest& m) {
  Answer a;
  const auto key =
      std::make_tuple(m.pv_mm_s, m.pa_mm_s2, m.pd_mm, m.av_mm_s, m.aa_mm_s2, m.ad_mm, m.y_mm);
  auto it = rae_.find(key);
  if (it == rae_.end()) {
    try {
      const motion::ProbingMove move =
          motion::probing_move_mm(m.pv_mm_s, m.pa_mm_s2, m.pd_mm, m.av_mm_s, m.aa_mm_s2, m.ad_mm);
      const double rae = simulator_.simulate(move, m.y_mm * 1e-3).errors_um.rae;
      it = rae_.emplace(key, rae).first;
    } catch (const std::exception& e) {
      a.status = static_cast<int>(Status::kInvalidInput);
      a.flags = compensation::kFlagInvalidInput;
      a.note = e.what();
      return a;
    }
  }
  a.rae_um = it->second;
  for (std::size_t i = 0; i < 3; ++i) a.correction_um[i] = a.rae_um * m.direction[i];
  a.flags = compensation::kFlagOk;
  a.interval_flags = compensation::kFlagOk | compensation::kFlagNoUncertainty;
  a.usable = std::isfinite(a.rae_um);
  if (!a.usable) a.note = "the simulation's RAE is not finite";
  return a;
}

}  // namespace cmmcomp::vc
