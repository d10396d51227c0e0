// SPDX-License-Identifier: MIT
/// @file The twin as the virtual controller's machine.
#include <cmmcomp/vc/twin_probe.hpp>

namespace cmmcomp::vc {

TwinProbe::TwinProbe(const dynamics::Machine& machine, const dynamics::MeasurementNoise& noise)
    : simulator_(machine), noise_(noise) {}

double TwinProbe::rae_um(const ProbeSetting& s, double y_mm, std::uint64_t index) {
  const auto key =
      std::make_tuple(s.pv_mm_s, s.pa_mm_s2, s.pd_mm, s.av_mm_s, s.aa_mm_s2, s.ad_mm, y_mm);
  auto it = clean_.find(key);
  if (it == clean_.end()) {
    // The twin moves along +X; its errors are signed along the motion, so they hold for −X too.
    const dynamics::SimulationResult r = simulator_.simulate(move_of(s), y_mm * 1e-3);
    it = clean_.emplace(key, r.errors_um).first;
  }
  return dynamics::add_noise(it->second, noise_, index).rae;
}

}  // namespace cmmcomp::vc
