// SPDX-License-Identifier: MIT
/// @file A correction source that predicts with a machine: the grey-box model of issue 38 (the
/// twin's equations with identified physical parameters) answering as an agent would.
///
/// Contract: ask() simulates the request's move (PV, PA, PD, AV, AA, AD, Y) on its machine at
/// the machine's controller timing (its dwell and smoothing: the cycle the program runs) and
/// answers its RAE with the correction RAE·d, usable, flagged kFlagNoUncertainty (a machine
/// carries no interval). A move the machine cannot simulate (outside its capabilities, not
/// plannable) is an Answer with usable = false and the reason in `note`. Setup-time
/// construction (throws ConfigError for a non-physical machine); ask() never throws.
/// Not the real-time path: a simulation per request, for the study and the virtual controller.
#pragma once

#include <cmmcomp/dynamics/bridge_model.hpp>
#include <cmmcomp/vc/correction_source.hpp>
#include <cstdint>
#include <map>
#include <string>
#include <tuple>

namespace cmmcomp::vc {

class TwinSource final : public CorrectionSource {
 public:
  TwinSource(std::string label, const dynamics::Machine& machine);
  Answer ask(const compensation::MoveRequest& move) override;
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }

 private:
  std::string label_;
  std::string where_;
  dynamics::BridgeSimulator simulator_;
  std::map<std::tuple<double, double, double, double, double, double, double>, double> rae_;
};

}  // namespace cmmcomp::vc
