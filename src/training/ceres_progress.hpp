// SPDX-License-Identifier: MIT
/// @file Forwards Ceres' per-iteration report to a plain (iteration, cost) callback.
#pragma once

#include <ceres/iteration_callback.h>

#include <functional>

namespace cmmcomp::training::detail {

class ProgressCallback final : public ceres::IterationCallback {
 public:
  /// `f` may be empty (then nothing is called); it must outlive the solve.
  explicit ProgressCallback(const std::function<void(int, double)>& f) : f_(f) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (f_) f_(s.iteration, s.cost);
    return ceres::SOLVER_CONTINUE;
  }

 private:
  const std::function<void(int, double)>& f_;
};

}  // namespace cmmcomp::training::detail
