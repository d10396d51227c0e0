// SPDX-License-Identifier: MIT
/// @file The twin as the I++ DME server's machine.
#include <cmmcomp/vc/ipp_twin_machine.hpp>
#include <exception>

namespace cmmcomp::vc {

IppTwinMachine::IppTwinMachine(const dynamics::Machine& machine,
                               const dynamics::MeasurementNoise& noise)
    : simulator_(machine), noise_(noise) {}

motion::ControllerCapabilities IppTwinMachine::capabilities() const {
  return simulator_.machine().capabilities;
}

// X and Z: the longest move motion::MoveLimits accepts; Y: the twin's carriage range (0 .. 2 m,
// BridgeSimulator::simulate).
ipp::Point3 IppTwinMachine::volume_min() const { return {-10000.0, 0.0, -10000.0}; }
ipp::Point3 IppTwinMachine::volume_max() const { return {10000.0, 2000.0, 10000.0}; }

ipp::Touch IppTwinMachine::probe(const ipp::ReconstructedMove& move, std::uint64_t index) {
  ipp::Touch t;
  const auto key = std::make_tuple(
      move.pv_mm_s, move.pa_mm_s2, move.pd_mm, move.av_mm_s, move.aa_mm_s2, move.ad_mm, move.y_mm);
  auto it = clean_.find(key);
  if (it == clean_.end()) {
    try {
      const dynamics::SimulationResult r = simulator_.simulate(move.move(), move.y_mm * 1e-3);
      it = clean_.emplace(key, std::make_pair(r.errors_um, r.instants.touch)).first;
    } catch (const std::exception& e) {
      t.problem = e.what();
      return t;
    }
  }
  t.ok = true;
  t.rae_um = dynamics::add_noise(it->second.first, noise_, index).rae;
  t.seconds = it->second.second;
  return t;
}

}  // namespace cmmcomp::vc
