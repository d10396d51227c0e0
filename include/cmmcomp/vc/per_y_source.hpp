// SPDX-License-Identifier: MIT
/// @file An agent per carriage position behind one label: a model per Y.
#pragma once

#include <cmath>
#include <cmmcomp/vc/correction_source.hpp>
#include <cstdio>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace cmmcomp::vc {

/// Forwards each move to the agent of its carriage position Y (to 1e-6 mm), as a controller
/// with one model per Y would (docs/planner.md, "Models per Y"). A move at a Y without an agent
/// is a refusal (usable = false) naming it; cmmcomp-vc checks before a run that every Y of the
/// program has one.
class PerYSource final : public CorrectionSource {
 public:
  static constexpr double kSameY = 1e-6;  // mm

  /// `agents`: (Y, agent) pairs with distinct Y, all under `label`.
  PerYSource(std::string label,
             std::vector<std::pair<double, std::unique_ptr<CorrectionSource>>> agents)
      : label_(std::move(label)), agents_(std::move(agents)) {
    for (const auto& [y, agent] : agents_) {
      where_ +=
          (where_.empty() ? "" : "; ") + std::string("Y ") + number(y) + ": " + agent->where();
    }
  }

  Answer ask(const compensation::MoveRequest& move) override {
    for (auto& [y, agent] : agents_) {
      if (std::fabs(y - move.y_mm) <= kSameY) return agent->ask(move);
    }
    Answer a;
    a.status = -1;
    a.note = "no agent of '" + label_ + "' for Y " + number(move.y_mm) + " mm";
    return a;
  }

  /// Whether a move at `y_mm` has an agent.
  bool serves(double y_mm) const noexcept {
    for (const auto& entry : agents_) {
      if (std::fabs(entry.first - y_mm) <= kSameY) return true;
    }
    return false;
  }

  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }

 private:
  static std::string number(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%g", v);
    return text;
  }

  std::string label_;
  std::string where_;
  std::vector<std::pair<double, std::unique_ptr<CorrectionSource>>> agents_;
};

}  // namespace cmmcomp::vc
