// SPDX-License-Identifier: MIT
/// @file The measuring machine of the virtual controller: the digital twin plus Table 1 noise.
#pragma once

#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/dynamics/noise.hpp>
#include <cmmcomp/vc/probe_setting.hpp>
#include <cstdint>
#include <map>
#include <memory>
#include <tuple>

namespace cmmcomp::vc {

/// RAE of the touch of one point [µm]. Implemented by the twin; tests use analytic fakes.
class TouchErrorModel {
 public:
  virtual ~TouchErrorModel() = default;
  /// RAE of point number `index` (program order; selects the noise stream) probed with `s` at
  /// carriage position `y_mm`.
  virtual double rae_um(const ProbeSetting& s, double y_mm, std::uint64_t index) = 0;
};

/// The twin (BridgeSimulator on a machine) with seeded measurement noise. Moves with the same
/// setting and Y are simulated once (the twin is deterministic); the noise of point `index`
/// depends only on (seed, index).
class TwinProbe final : public TouchErrorModel {
 public:
  /// Setup only; throws ConfigError for a non-physical machine.
  TwinProbe(const dynamics::Machine& machine, const dynamics::MeasurementNoise& noise);
  double rae_um(const ProbeSetting& s, double y_mm, std::uint64_t index) override;

 private:
  dynamics::BridgeSimulator simulator_;
  dynamics::MeasurementNoise noise_;
  std::map<std::tuple<double, double, double, double, double, double, double>,
           errors::DynamicErrors>
      clean_;
};

}  // namespace cmmcomp::vc
