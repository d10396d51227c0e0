// SPDX-License-Identifier: MIT
/// @file The bridge model integrated exactly in its linear part (private to the twin).
///
/// Everything in the model is linear except the Coulomb drag's tanh(v_h / v₀), and the commanded
/// profile is a cubic in time inside each segment. So the state, augmented with the command
/// (v_c, a_c, jerk) and with the Coulomb fraction as a line in time (f₀ + f₁ (t − tₙ)), obeys
/// z' = M z exactly, and one step is z ← exp(M h) z: the structural mode, the servo and the hose
/// link are propagated without truncation error at any step size. The one approximation is the
/// Coulomb fraction's line over a step (its value and slope at the step's start, a local error
/// of order h³ in the drag), which is why the step is bounded (SimulationOptions). CVODE, which
/// has to resolve the lightly damped mode with ~20 steps per period, stays the reference
/// (Integration::kCvode) and a test holds the two together (docs/machine-model.md,
/// "Integration").
#pragma once

#include <array>
#include <functional>
#include <limits>

#include "bridge_equations.hpp"

namespace cmmcomp::dynamics {

class ExponentialIntegrator {
 public:
  /// The model's states plus v_c, a_c, jerk, f₀, f₁ (the largest: a machine without a second
  /// mode uses the leading kBaseStates + 5).
  static constexpr int kAugmented = equations::kStates + 5;
  /// Row-major. Plain arrays and loops in a fixed order, not a SIMD library: the twin's data
  /// must be the same bits in every build (the release preset's -march=x86-64-v3 and the
  /// portable sanitizer builds), because the shipped models are retrained from it and compared
  /// by its hash (ctest default_model_reproducible); a last-digit change of one sample moves the
  /// retrained model by ~0.5 µm.
  using Matrix = std::array<double, std::size_t{kAugmented} * kAugmented>;
  using Vector = std::array<double, kAugmented>;
  /// Receives a sample: its time [s] and the model's states (Coefficients::states values).
  using Sink = std::function<void(double t, const double* y)>;

  /// `max_step_s` > 0 bounds the step; each segment is split into equal steps no longer.
  ExponentialIntegrator(const equations::Coefficients& c, double max_step_s);

  /// Advances `y` (the model's states) from the start to the end of `segment`. Calls `sink`, in
  /// time order, at every extremum of the tip error inside a step (interpolated, cubic Hermite),
  /// at every multiple of `trace_dt` inside the segment when trace_dt > 0 (interpolated), and at
  /// every step's end (exact), the segment's end included. The times `sink` sees are strictly
  /// increasing over the integrator's life: a sample whose time rounds onto one already given (an
  /// extremum at t0 + s·h with s close to 0 or 1, a grid point on an extremum, a segment shorter
  /// than the time's resolution) is not given again; the state still advances.
  void advance(const motion::Segment& segment, double* y, double trace_dt, const Sink& sink);

  long steps() const noexcept { return steps_; }
  long matrix_exponentials() const noexcept { return exponentials_; }
  long extrema() const noexcept { return extrema_; }

 private:
  const Matrix& transition(double h);

  equations::Coefficients c_;
  double max_step_;
  int n_;  ///< augmented states in use: the machine's states + 5
  Matrix m_;
  struct Cached {
    double h = -1.0;
    Matrix phi;
  };
  std::array<Cached, 4> cache_{};
  int next_slot_ = 0;
  long steps_ = 0;
  long exponentials_ = 0;
  long extrema_ = 0;
  /// The last time given to a sink; samples at or before it are not given.
  double last_time_ = -std::numeric_limits<double>::infinity();
};

}  // namespace cmmcomp::dynamics
