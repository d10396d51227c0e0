// SPDX-License-Identifier: MIT
/// @file Commanded motion of one probing move: positioning, then approach to the touch.
///
/// A probing move (Wei et al. 2019, Fig. 1) has two phases along one axis:
///  1. positioning over PD at PV with acceleration PA, from rest to rest;
///  2. an optional settling dwell at rest at the pre-hit point (a controller setting);
///  3. approach from rest over AD at AV with acceleration AA, ending at the touch point while
///     still moving (a touch-trigger probe triggers in motion). If AD is too short to reach AV
///     the probe touches while still accelerating, and the profile says so.
/// Without a jerk limit or smoothing the phases are trapezoidal (triangular when the distance is
/// too short to reach the speed); with one they are 7-segment S-curves (or the shorter
/// jerk-limited forms). Command smoothing (a controller setting) ramps every acceleration change
/// over a fixed time: a jerk limit of accel / smoothing in each phase. Every case is solved in
/// closed form, so distances are hit to rounding error.
///
/// Positions are measured from the start of the positioning phase, in the direction of motion.
/// AV > PV is allowed: the two phases are planned independently.
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/paper_reference.hpp>
#include <cmmcomp/status.hpp>

namespace cmmcomp::motion {

/// The commanded parameters of one probing move. SI units.
struct ProbingMove {
  double positioning_speed = 0.0;     ///< PV [m/s]
  double positioning_accel = 0.0;     ///< PA [m/s^2]
  double positioning_distance = 0.0;  ///< PD [m]
  double approach_speed = 0.0;        ///< AV [m/s]
  double approach_accel = 0.0;        ///< AA [m/s^2]
  double approach_distance = 0.0;     ///< AD [m]
  double jerk = 0.0;                  ///< jerk limit [m/s^3]; 0 = none (trapezoidal profiles)
  double dwell = 0.0;                 ///< settling dwell at rest at the pre-hit point [s]; 0 = none
  double smoothing = 0.0;  ///< command smoothing: each acceleration change ramps over this [s]
};

/// A move given in the units of the tools, the dataset CSV and the compensator (mm, mm/s,
/// mm/s²), in SI units, without a jerk limit.
constexpr ProbingMove probing_move_mm(double pv_mm_s,
                                      double pa_mm_s2,
                                      double pd_mm,
                                      double av_mm_s,
                                      double aa_mm_s2,
                                      double ad_mm) noexcept {
  return ProbingMove{pv_mm_s * 1e-3,
                     pa_mm_s2 * 1e-3,
                     pd_mm * 1e-3,
                     av_mm_s * 1e-3,
                     aa_mm_s2 * 1e-3,
                     ad_mm * 1e-3,
                     0.0,
                     0.0,
                     0.0};
}

/// The paper's baseline move (PV 40 mm/s, PA 200 mm/s^2, PD 40 mm, AV 12 mm/s, AA 60 mm/s^2,
/// AD 10 mm), in SI units.
constexpr ProbingMove baseline_move() noexcept {
  // mm / 1000 is the double nearest the SI value, as the literal 0.040 is (bit-identical).
  constexpr paper::BaselineMove kB = paper::kBaseline;
  return ProbingMove{kB.pv_mm_s / 1000.0,
                     kB.pa_mm_s2 / 1000.0,
                     kB.pd_mm / 1000.0,
                     kB.av_mm_s / 1000.0,
                     kB.aa_mm_s2 / 1000.0,
                     kB.ad_mm / 1000.0,
                     0.0,
                     0.0,
                     0.0};
}

/// Accepted ranges of the move parameters (inclusive). Values outside are rejected with
/// Status::kInvalidInput rather than planned into a degenerate profile.
struct MoveLimits {
  static constexpr double kMinDistance = 1e-6;  ///< [m]
  static constexpr double kMaxDistance = 10.0;  ///< [m]
  static constexpr double kMinSpeed = 1e-5;     ///< [m/s]
  static constexpr double kMaxSpeed = 10.0;     ///< [m/s]
  static constexpr double kMinAccel = 1e-4;     ///< [m/s^2]
  static constexpr double kMaxAccel = 1000.0;   ///< [m/s^2]
  static constexpr double kMinJerk = 1e-3;      ///< [m/s^3] (0 also accepted: no jerk limit)
  static constexpr double kMaxJerk = 1e7;       ///< [m/s^3]
  static constexpr double kMaxDwell = 60.0;     ///< [s] (0 = no dwell)
  static constexpr double kMaxSmoothing = 1.0;  ///< [s] (0 = no smoothing)
};

/// The first parameter of a move outside MoveLimits (or NaN), for a message that names it:
/// `label` is null when every parameter is accepted. SI values; RT-safe.
struct MoveParameterProblem {
  const char* label =
      nullptr;            ///< "PV", "PA", "PD", "AV", "AA", "AD", "jerk", "dwell", "smoothing"
  const char* unit = "";  ///< "m/s", "m/s^2", "m", "m/s^3", "s"
  double value = 0.0, min = 0.0, max = 0.0;
};
[[nodiscard]] MoveParameterProblem first_invalid_parameter(const ProbingMove& m) noexcept;

/// Commanded state at one instant.
struct MotionState {
  double position = 0.0;      ///< [m]
  double velocity = 0.0;      ///< [m/s]
  double acceleration = 0.0;  ///< [m/s^2]
  double jerk = 0.0;          ///< [m/s^3] (0 inside trapezoidal segments)
};

/// The instants that define the four dynamic-error parameters [s], from the move start.
/// Ordered: 0 <= accel_end <= decel_start <= positioning_end <= approach_start <= touch.
struct PhaseInstants {
  double positioning_accel_end = 0.0;    ///< commanded acceleration first back to zero
  double positioning_decel_start = 0.0;  ///< end of the cruise at PV: deceleration starts (RPE)
  double positioning_end = 0.0;          ///< positioning at rest at the pre-hit point
  double approach_start = 0.0;           ///< end of the dwell: the approach starts
  double approach_accel_end = 0.0;       ///< approach reaches AV (= touch if it never does)
  double touch = 0.0;                    ///< the probe touches (RAE); end of the move
};

/// One piece of constant jerk: x(τ) = p0 + v0 τ + a0 τ²/2 + j τ³/6 for τ in [0, duration].
struct Segment {
  double start_time = 0.0;  ///< [s]
  double duration = 0.0;    ///< [s]
  double p0 = 0.0;          ///< position at start [m]
  double v0 = 0.0;          ///< velocity at start [m/s]
  double a0 = 0.0;          ///< acceleration at start [m/s^2]
  double jerk = 0.0;        ///< constant jerk [m/s^3]

  constexpr double end_time() const noexcept { return start_time + duration; }
  /// State at `tau` seconds into the segment. RT-safe.
  constexpr MotionState at(double tau) const noexcept {
    return MotionState{p0 + tau * (v0 + tau * (a0 / 2.0 + tau * jerk / 6.0)),
                       v0 + tau * (a0 + tau * jerk / 2.0),
                       a0 + tau * jerk,
                       jerk};
  }
};

namespace detail {

constexpr bool in_range(double x, double lo, double hi) noexcept {
  return x >= lo && x <= hi;  // false for NaN
}

/// Time to accelerate from rest to `v` with acceleration limit `a` and jerk limit `j`
/// (j = 0: no jerk limit). The velocity curve is point-symmetric about its middle, so the
/// distance covered is v * time / 2.
inline double accel_time(double v, double a, double j) noexcept {
  if (j == 0.0) return v / a;
  if (v * j >= a * a) return v / a + a / j;  // reaches a: ramp up, hold, ramp down
  return 2.0 * std::sqrt(v / j);             // never reaches a
}

/// Largest speed reachable over a rest-to-rest distance `d` (accelerate, then decelerate at
/// once), given limits `a` and `j`. Closed form for each case.
inline double rest_to_rest_peak_speed(double d, double a, double j) noexcept {
  if (j == 0.0) return std::sqrt(d * a);
  // Case reaching a: v^2 + v a^2/j - d a = 0, solved in the cancellation-free form.
  const double b = a * a / j;
  const double v = 2.0 * d * a / (b + std::sqrt(b * b + 4.0 * d * a));
  if (v >= b) return v;
  // Case never reaching a: 2 v sqrt(v/j) = d.
  return std::cbrt(d * d * j / 4.0);
}

/// Time into segment `s` at which its position reaches `target` (clamped to the segment).
/// The velocity is non-negative inside every planned segment, so the position is monotone.
/// Closed form where the polynomial is at most quadratic or a pure cube; otherwise Newton's
/// method safeguarded by bisection, at most 100 steps. RT-safe.
inline double time_to_reach(const Segment& s, double target) noexcept {
  const double c = target - s.p0;
  if (!(c > 0.0)) return 0.0;
  if (s.at(s.duration).position <= target) return s.duration;
  if (s.jerk == 0.0) {
    const double disc = s.v0 * s.v0 + 2.0 * s.a0 * c;
    const double tau = 2.0 * c / (s.v0 + std::sqrt(disc > 0.0 ? disc : 0.0));
    return tau < s.duration ? tau : s.duration;
  }
  if (s.v0 == 0.0 && s.a0 == 0.0) {
    const double tau = std::cbrt(6.0 * c / s.jerk);
    return tau < s.duration ? tau : s.duration;
  }
  double lo = 0.0;
  double hi = s.duration;
  double tau = 0.5 * (lo + hi);
  for (int i = 0; i < 100; ++i) {
    const MotionState st = s.at(tau);
    const double f = st.position - target;
    if (f > 0.0) {
      hi = tau;
    } else {
      lo = tau;
    }
    const double newton = st.velocity > 0.0 ? tau - f / st.velocity : -1.0;
    const double next = (newton > lo && newton < hi) ? newton : 0.5 * (lo + hi);
    if (next == tau || hi - lo <= 4.0 * 2.2e-16 * s.duration) break;
    tau = next;
  }
  return tau;
}

/// Up to 8 segments of one phase (a 7-segment S-curve and the dwell after it), chained from
/// rest at time 0 and position 0.
struct PhasePlan {
  std::array<Segment, 8> segments{};
  int count = 0;

  double end_time() const noexcept {
    return count == 0 ? 0.0 : segments[static_cast<unsigned>(count - 1)].end_time();
  }
  MotionState end_state() const noexcept {
    if (count == 0) return MotionState{};
    const Segment& s = segments[static_cast<unsigned>(count - 1)];
    return s.at(s.duration);
  }
  /// Appends a piece. Jerk pieces continue the acceleration; constant-acceleration pieces of a
  /// trapezoidal profile step it to `accel`. Zero-length pieces are dropped (no kink).
  void push(double duration, double jerk, double accel) noexcept {
    if (!(duration > 0.0)) return;
    const MotionState e = end_state();
    Segment s;
    s.start_time = end_time();
    s.duration = duration;
    s.p0 = e.position;
    s.v0 = e.velocity;
    s.a0 = jerk == 0.0 ? accel : e.acceleration;
    s.jerk = jerk;
    segments[static_cast<unsigned>(count++)] = s;
  }
  /// Speed change by `sign * v` from a constant speed, at limits (a, j): the acceleration (sign
  /// +1) or deceleration (sign -1) part of a profile.
  void ramp(double v, double a, double j, double sign) noexcept {
    if (j == 0.0) {
      push(v / a, 0.0, sign * a);
    } else if (v * j >= a * a) {
      push(a / j, sign * j, 0.0);
      push(v / a - a / j, 0.0, sign * a);
      push(a / j, -sign * j, 0.0);
    } else {
      const double t = std::sqrt(v / j);
      push(t, sign * j, 0.0);
      push(t, -sign * j, 0.0);
    }
  }
};

}  // namespace detail

/// The planned commanded motion of one probing move.
class MoveProfile {
 public:
  /// 7 segments for the positioning S-curve, 1 dwell, 3 for the approach acceleration, 1 cruise.
  static constexpr int kMaxSegments = 12;

  /// Plans `move` into `out`. RT-safe (no allocation, bounded time).
  /// Returns kOk, or kInvalidInput (NaN, inf, or a parameter outside MoveLimits); on error
  /// `out` is left untouched.
  [[nodiscard]] static Status plan(const ProbingMove& move, MoveProfile& out) noexcept;

  /// Commanded state at `t` [s]. Before 0 the axis is at rest at 0; after the touch the last
  /// segment's polynomial continues (the axis keeps moving until the controller stops it).
  /// RT-safe.
  MotionState sample(double t) const noexcept {
    if (!(t > 0.0)) return MotionState{};
    int i = 0;
    while (i < segment_count_ - 1 && t >= segments_[static_cast<unsigned>(i)].end_time()) ++i;
    const Segment& s = segments_[static_cast<unsigned>(i)];
    return s.at(t - s.start_time);
  }

  const PhaseInstants& instants() const noexcept { return instants_; }
  const ProbingMove& move() const noexcept { return move_; }
  /// Total duration from start to touch [s].
  double duration() const noexcept { return instants_.touch; }
  /// Peak speed of the positioning phase (< PV when PD is too short to reach PV) [m/s].
  double positioning_peak_speed() const noexcept { return positioning_peak_speed_; }
  /// True when the positioning phase cruises at PV.
  bool positioning_reaches_speed() const noexcept { return positioning_reaches_speed_; }
  /// True when the approach reaches AV before the touch.
  bool approach_reaches_speed() const noexcept { return approach_reaches_speed_; }

  int segment_count() const noexcept { return segment_count_; }
  /// Segment `i`, 0 <= i < segment_count(). Segment boundaries are the profile's kinks (where
  /// acceleration or jerk jumps): an integrator must stop at each one.
  const Segment& segment(int i) const noexcept { return segments_[static_cast<unsigned>(i)]; }

 private:
  void append(const detail::PhasePlan& phase, double t0, double p0) noexcept {
    for (int i = 0; i < phase.count; ++i) {
      Segment s = phase.segments[static_cast<unsigned>(i)];
      s.start_time += t0;
      s.p0 += p0;
      segments_[static_cast<unsigned>(segment_count_++)] = s;
    }
  }

  ProbingMove move_{};
  PhaseInstants instants_{};
  std::array<Segment, kMaxSegments> segments_{};
  int segment_count_ = 0;
  double positioning_peak_speed_ = 0.0;
  bool positioning_reaches_speed_ = false;
  bool approach_reaches_speed_ = false;
};

inline MoveParameterProblem first_invalid_parameter(const ProbingMove& m) noexcept {
  using L = MoveLimits;
  using detail::in_range;
  const struct {
    const char* label;
    const char* unit;
    double value, min, max;
  } checks[] = {
      {"PV", "m/s", m.positioning_speed, L::kMinSpeed, L::kMaxSpeed},
      {"PA", "m/s^2", m.positioning_accel, L::kMinAccel, L::kMaxAccel},
      {"PD", "m", m.positioning_distance, L::kMinDistance, L::kMaxDistance},
      {"AV", "m/s", m.approach_speed, L::kMinSpeed, L::kMaxSpeed},
      {"AA", "m/s^2", m.approach_accel, L::kMinAccel, L::kMaxAccel},
      {"AD", "m", m.approach_distance, L::kMinDistance, L::kMaxDistance},
      {"dwell", "s", m.dwell, 0.0, L::kMaxDwell},
      {"smoothing", "s", m.smoothing, 0.0, L::kMaxSmoothing},
  };
  for (const auto& c : checks) {
    if (!in_range(c.value, c.min, c.max)) return {c.label, c.unit, c.value, c.min, c.max};
  }
  if (m.jerk != 0.0 && !in_range(m.jerk, L::kMinJerk, L::kMaxJerk)) {
    return {"jerk", "m/s^3", m.jerk, L::kMinJerk, L::kMaxJerk};
  }
  return {};
}

inline Status MoveProfile::plan(const ProbingMove& m, MoveProfile& out) noexcept {
  if (first_invalid_parameter(m).label != nullptr) return Status::kInvalidInput;

  MoveProfile p;
  p.move_ = m;
  // Smoothing ramps each acceleration change over `smoothing` seconds: per phase, a jerk limit of
  // accel / smoothing (the tighter of it and the move's own jerk limit).
  auto phase_jerk = [&m](double accel) {
    if (!(m.smoothing > 0.0)) return m.jerk;
    const double smoothed = accel / m.smoothing;
    return m.jerk > 0.0 && m.jerk < smoothed ? m.jerk : smoothed;
  };

  // Positioning: rest to rest over PD; triangular (or its jerk-limited form) when PD is short.
  detail::PhasePlan positioning;
  {
    const double d = m.positioning_distance;
    const double a = m.positioning_accel;
    const double j = phase_jerk(a);
    double v = m.positioning_speed;
    const double ramp_distance = v * detail::accel_time(v, a, j);  // both ramps together
    double cruise = 0.0;
    if (ramp_distance <= d) {
      cruise = (d - ramp_distance) / v;
      p.positioning_reaches_speed_ = true;
    } else {
      v = detail::rest_to_rest_peak_speed(d, a, j);
    }
    p.positioning_peak_speed_ = v;
    positioning.ramp(v, a, j, 1.0);
    p.instants_.positioning_accel_end = positioning.end_time();
    positioning.push(cruise, 0.0, 0.0);
    p.instants_.positioning_decel_start = positioning.end_time();
    positioning.ramp(v, a, j, -1.0);
    p.instants_.positioning_end = positioning.end_time();
    positioning.push(m.dwell, 0.0, 0.0);
    p.instants_.approach_start = positioning.end_time();
  }

  // Approach: from rest at PD, accelerate towards AV, cruise; touch after AD.
  detail::PhasePlan approach;
  int approach_ramp_segments = 0;  // segments up to the end of the approach acceleration
  {
    const double d = m.approach_distance;
    const double v = m.approach_speed;
    const double j = phase_jerk(m.approach_accel);
    const double d_acc = v * detail::accel_time(v, m.approach_accel, j) / 2.0;
    approach.ramp(v, m.approach_accel, j, 1.0);
    if (d >= d_acc) {
      p.approach_reaches_speed_ = true;
      approach_ramp_segments = approach.count;
      approach.push((d - d_acc) / v, 0.0, 0.0);
    } else {
      // The probe touches while accelerating: cut the ramp where it has covered AD.
      int cut = 0;
      while (cut < approach.count - 1) {
        const Segment& s = approach.segments[static_cast<unsigned>(cut)];
        if (s.at(s.duration).position >= d) break;
        ++cut;
      }
      Segment& s = approach.segments[static_cast<unsigned>(cut)];
      s.duration = detail::time_to_reach(s, d);
      approach.count = cut + 1;
      approach_ramp_segments = approach.count;
    }
  }

  // The approach is anchored on the exact pre-hit point, so rounding in the positioning chain
  // never shifts the touch point.
  p.append(positioning, 0.0, 0.0);
  p.append(approach, p.instants_.approach_start, m.positioning_distance);
  // Every instant is read off the appended segments, so it equals a segment boundary to the
  // last bit (an integrator stopping at the boundaries lands exactly on the instants).
  const int first_approach = p.segment_count_ - approach.count;
  p.instants_.approach_accel_end =
      p.segments_[static_cast<unsigned>(first_approach + approach_ramp_segments - 1)].end_time();
  p.instants_.touch = p.segments_[static_cast<unsigned>(p.segment_count_ - 1)].end_time();
  out = p;
  return Status::kOk;
}

}  // namespace cmmcomp::motion
