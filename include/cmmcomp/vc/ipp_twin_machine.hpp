// SPDX-License-Identifier: MIT
/// @file The digital twin as the machine of the I++ DME server (`cmmcomp-sim serve-ipp`,
/// docs/protocol-ippdme.md, "The twin behind the server").
///
/// A PtMeas's probing move (ipp/move_rule.hpp) runs on the twin (BridgeSimulator::simulate: the
/// machine's own dwell and smoothing) with the carriage at the nominal point's Y; its RAE, with
/// the seeded repeatability noise of point `index` when enabled, is the error at the touch along
/// the approach direction d. The twin models the X drive: a point probed along Y, Z or an oblique
/// IJK gets the error the X drive would have on the same move along d (every axis is taken to
/// behave as the X drive). The working volume is X and Z within ±10 m and the twin's carriage
/// range, Y in 0 .. 2000 mm. Setup-level code: allocates; probe() reports the twin's refusals
/// (a setting outside the machine's capabilities, an invalid move) as a Touch that is not ok.
#pragma once

#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/noise.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <map>
#include <tuple>

namespace cmmcomp::vc {

class IppTwinMachine final : public ipp::Machine {
 public:
  /// Setup only; throws ConfigError for a non-physical machine.
  IppTwinMachine(const dynamics::Machine& machine, const dynamics::MeasurementNoise& noise);

  motion::ControllerCapabilities capabilities() const override;
  ipp::Point3 volume_min() const override;
  ipp::Point3 volume_max() const override;
  ipp::Touch probe(const ipp::ReconstructedMove& move, std::uint64_t index) override;

 private:
  dynamics::BridgeSimulator simulator_;
  dynamics::MeasurementNoise noise_;
  std::map<std::tuple<double, double, double, double, double, double, double>,
           std::pair<errors::DynamicErrors, double>>
      clean_;  ///< the twin is deterministic: each move and Y simulated once (errors, seconds)
};

}  // namespace cmmcomp::vc
