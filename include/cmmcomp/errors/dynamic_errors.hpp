// SPDX-License-Identifier: MIT
/// @file The four dynamic-error parameters MPE, RPE, MAE, RAE of one probing move.
///
/// The single definition used by the simulator, the tools and the tests (docs/dynamic-errors.md).
/// Given the error trace e(t) = (x_tip(t) − x_scale(t)) · d, with d = ±1 the direction of motion:
///  - MPE = max |e| over the positioning phase [0, positioning_end];
///  - RPE = e(positioning_decel_start), the end of the cruise at PV, signed (positive: tip
///    ahead of the scale reading);
///  - MAE = max |e| over the approach phase [approach_start, touch];
///  - RAE = e(touch), signed: the error of the measured point.
/// The instants come from the move profile, never from the trace. A sampled trace is linearly
/// interpolated at the instants, and the maxima include the interpolated phase ends.
#pragma once

#include <cmath>
#include <cmmcomp/motion/move_profile.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>

namespace cmmcomp::errors {

/// The four parameters, in the unit of the trace they came from (µm in files and tools).
struct DynamicErrors {
  double mpe = 0.0;  ///< maximum positioning error (magnitude)
  double rpe = 0.0;  ///< residual positioning error (signed in the direction of motion)
  double mae = 0.0;  ///< maximum approach error (magnitude)
  double rae = 0.0;  ///< residual approach error (signed in the direction of motion)
};

/// A sampled error trace: `count` samples of time [s] and raw error x_tip − x_scale (any unit),
/// times strictly increasing.
struct TraceView {
  const double* time = nullptr;
  const double* error = nullptr;
  std::size_t count = 0;
};

namespace detail {

/// Index i with time[i] <= t < time[i+1] (count >= 2, t inside the trace), by bisection.
inline std::size_t bracket(const TraceView& trace, double t) noexcept {
  std::size_t lo = 0;
  std::size_t hi = trace.count - 1;
  while (hi - lo > 1) {
    const std::size_t mid = lo + (hi - lo) / 2;
    if (trace.time[mid] <= t) {
      lo = mid;
    } else {
      hi = mid;
    }
  }
  return lo;
}

inline double interpolate(const TraceView& trace, double t) noexcept {
  const std::size_t i = bracket(trace, t);
  const double t0 = trace.time[i];
  const double t1 = trace.time[i + 1];
  const double w = (t - t0) / (t1 - t0);
  return trace.error[i] + w * (trace.error[i + 1] - trace.error[i]);
}

/// max |e| over [a, b]: the samples inside plus the interpolated ends.
inline double max_abs(const TraceView& trace, double a, double b) noexcept {
  double m = std::fabs(interpolate(trace, a));
  const double end = std::fabs(interpolate(trace, b));
  if (end > m) m = end;
  for (std::size_t i = bracket(trace, a) + 1; i < trace.count && trace.time[i] < b; ++i) {
    const double v = std::fabs(trace.error[i]);
    if (v > m) m = v;
  }
  return m;
}

}  // namespace detail

/// Computes MPE, RPE, MAE, RAE from `trace` and the move's `instants`; `direction` is +1 or −1.
/// RT-safe (no allocation; O(samples)). Returns kOk; kInvalidInput when direction is not ±1,
/// a sample is NaN/inf, times are not strictly increasing, or the instants are not ordered
/// 0 <= accel_end <= decel_start <= positioning_end <= approach_start <= touch; kTraceTooShort when
/// the trace has fewer than two samples or does not cover [0, touch]. `out` is untouched on error.
[[nodiscard]] inline Status extract_dynamic_errors(const TraceView& trace,
                                                   const motion::PhaseInstants& instants,
                                                   int direction,
                                                   DynamicErrors& out) noexcept {
  if (direction != 1 && direction != -1) return Status::kInvalidInput;
  const motion::PhaseInstants& s = instants;
  if (!(0.0 <= s.positioning_accel_end && s.positioning_accel_end <= s.positioning_decel_start &&
        s.positioning_decel_start <= s.positioning_end && s.positioning_end <= s.approach_start &&
        s.approach_start <= s.touch && std::isfinite(s.touch))) {
    return Status::kInvalidInput;
  }
  if (trace.time == nullptr || trace.error == nullptr || trace.count < 2) {
    return Status::kTraceTooShort;
  }
  for (std::size_t i = 0; i < trace.count; ++i) {
    if (!std::isfinite(trace.time[i]) || !std::isfinite(trace.error[i])) {
      return Status::kInvalidInput;
    }
    if (i > 0 && !(trace.time[i] > trace.time[i - 1])) return Status::kInvalidInput;
  }
  if (trace.time[0] > 0.0 || trace.time[trace.count - 1] < s.touch) {
    return Status::kTraceTooShort;
  }
  const double d = direction;
  DynamicErrors e;
  e.mpe = detail::max_abs(trace, 0.0, s.positioning_end);
  e.rpe = d * detail::interpolate(trace, s.positioning_decel_start);
  e.mae = detail::max_abs(trace, s.approach_start, s.touch);
  e.rae = d * detail::interpolate(trace, s.touch);
  out = e;
  return Status::kOk;
}

}  // namespace cmmcomp::errors
