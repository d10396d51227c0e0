// SPDX-License-Identifier: MIT
/// @file The exponential integrator of the bridge model (exponential_integrator.hpp).
#include "exponential_integrator.hpp"

#include <algorithm>
#include <cmath>

namespace cmmcomp::dynamics {
namespace {

using namespace equations;

// The augmented vector: the base states, the command and the Coulomb line, then the second
// mode's states when the machine has one. A machine without it runs the same arithmetic, in the
// same order, as before the second mode existed (the twin's data stay the same bits).
constexpr int kVc = kBaseStates;      // commanded velocity
constexpr int kAc = kBaseStates + 1;  // commanded acceleration
constexpr int kJerk = kBaseStates + 2;
constexpr int kF0 = kBaseStates + 3;  // Coulomb fraction at the step's start, then along its line
constexpr int kF1 = kBaseStates + 4;  // its slope over the step [1/s]
constexpr int kForcing = 5;

constexpr int kN = ExponentialIntegrator::kAugmented;  // the stride; n ≤ kN are in use
using Matrix = ExponentialIntegrator::Matrix;
using Vector = ExponentialIntegrator::Vector;

/// Position of model state `i` in the augmented vector.
constexpr int aug(int i) noexcept { return i < kBaseStates ? i : i + kForcing; }

constexpr std::size_t at(int r, int c) noexcept {
  return static_cast<std::size_t>(r) * std::size_t{kN} + static_cast<std::size_t>(c);
}

/// a · b (row-major, the leading n × n block), each element summed in column order.
Matrix multiply(const Matrix& a, const Matrix& b, int n) noexcept {
  Matrix p{};
  for (int r = 0; r < n; ++r) {
    for (int c = 0; c < n; ++c) {
      double sum = 0.0;
      for (int k = 0; k < n; ++k) sum += a[at(r, k)] * b[at(k, c)];
      p[at(r, c)] = sum;
    }
  }
  return p;
}

/// m · v (the leading n × n block), each element summed in column order.
Vector apply(const Matrix& m, const Vector& v, int n) noexcept {
  Vector out{};
  for (int r = 0; r < n; ++r) {
    double sum = 0.0;
    for (int k = 0; k < n; ++k) sum += m[at(r, k)] * v[static_cast<std::size_t>(k)];
    out[static_cast<std::size_t>(r)] = sum;
  }
  return out;
}

/// exp(a) of the leading n × n block by scaling and squaring: a / 2^s has a 1-norm ≤ 1/2, its
/// Taylor series to order 20 (truncation below 0.5^21 / 21! ≈ 1e-26 of the norm), then s
/// squarings. Deterministic.
Matrix exponential(const Matrix& a, int n) {
  double norm = 0.0;  // the 1-norm: the largest column sum of |a|
  for (int c = 0; c < n; ++c) {
    double col = 0.0;
    for (int r = 0; r < n; ++r) col += std::abs(a[at(r, c)]);
    norm = std::max(norm, col);
  }
  int squarings = 0;
  while (norm > 0.5 && squarings < 64) {
    norm *= 0.5;
    ++squarings;
  }
  const double scale = std::ldexp(1.0, -squarings);
  Matrix x{};
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = a[i] * scale;
  Matrix result{};
  Matrix term{};
  for (int i = 0; i < n; ++i) result[at(i, i)] = term[at(i, i)] = 1.0;
  for (int k = 1; k <= 20; ++k) {
    term = multiply(term, x, n);
    const double inv_k = 1.0 / k;
    for (std::size_t i = 0; i < term.size(); ++i) {
      term[i] *= inv_k;
      result[i] += term[i];
    }
  }
  for (int i = 0; i < squarings; ++i) result = multiply(result, result, n);
  return result;
}

/// Cubic Hermite interpolation at s ∈ [0, 1] of a step of length h.
double hermite(double s, double h, double p0, double d0, double p1, double d1) noexcept {
  const double s2 = s * s;
  const double s3 = s2 * s;
  return (2 * s3 - 3 * s2 + 1) * p0 + (s3 - 2 * s2 + s) * h * d0 + (-2 * s3 + 3 * s2) * p1 +
         (s3 - s2) * h * d1;
}

/// The s ∈ (0, 1) where the cubic Hermite interpolant of (p0, d0) → (p1, d1) has zero slope,
/// given that d0 and d1 have opposite signs (so exactly one such s exists).
double hermite_stationary_point(double h, double p0, double d0, double p1, double d1) noexcept {
  const double m0 = h * d0;
  const double m1 = h * d1;
  const double a = 3.0 * (2.0 * p0 + m0 - 2.0 * p1 + m1);  // slope = a s² + b s + m0
  const double b = 2.0 * (-3.0 * p0 - 2.0 * m0 + 3.0 * p1 - m1);
  double s = 0.5;
  if (std::abs(a) < 1e-14 * (std::abs(b) + std::abs(m0))) {
    s = -m0 / b;  // the slope is linear
  } else {
    const double disc = std::max(0.0, b * b - 4.0 * a * m0);
    const double q = -0.5 * (b + std::copysign(std::sqrt(disc), b));
    const double r1 = q / a;
    const double r2 = q != 0.0 ? m0 / q : r1;
    s = (r1 > 0.0 && r1 < 1.0) ? r1 : r2;
  }
  return std::clamp(s, 0.0, 1.0);
}

}  // namespace

ExponentialIntegrator::ExponentialIntegrator(const Coefficients& c, double max_step_s)
    : c_(c), max_step_(max_step_s), n_(c.states + kForcing) {
  // M's columns are the right-hand side's response to each augmented state alone: the equations
  // stay written once (bridge_equations.hpp), linear once the Coulomb fraction is a state.
  m_.fill(0.0);
  double dy[kStates];
  auto column = [&](int col, const motion::MotionState& cmd, const double* y, double f) {
    derivatives_given_coulomb(c_, cmd, y, f, dy);
    for (int r = 0; r < c_.states; ++r) m_[at(aug(r), col)] = dy[r];
  };
  const motion::MotionState rest{};
  for (int i = 0; i < c_.states; ++i) {
    double y[kStates] = {};
    y[i] = 1.0;
    column(aug(i), rest, y, 0.0);
  }
  const double zero[kStates] = {};
  column(kVc, motion::MotionState{0.0, 1.0, 0.0, 0.0}, zero, 0.0);
  column(kAc, motion::MotionState{0.0, 0.0, 1.0, 0.0}, zero, 0.0);
  column(kF0, rest, zero, 1.0);
  m_[at(kVc, kAc)] = 1.0;    // v_c' = a_c
  m_[at(kAc, kJerk)] = 1.0;  // a_c' = jerk
  m_[at(kF0, kF1)] = 1.0;    // f' = f₁ along the step
}

const ExponentialIntegrator::Matrix& ExponentialIntegrator::transition(double h) {
  for (const Cached& slot : cache_) {
    if (slot.h == h) return slot.phi;
  }
  Cached& slot = cache_[static_cast<std::size_t>(next_slot_)];
  next_slot_ = (next_slot_ + 1) % static_cast<int>(cache_.size());
  Matrix mh{};
  for (std::size_t i = 0; i < mh.size(); ++i) mh[i] = m_[i] * h;
  slot.phi = exponential(mh, n_);
  slot.h = h;
  ++exponentials_;
  return slot.phi;
}

void ExponentialIntegrator::advance(const motion::Segment& segment,
                                    double* y,
                                    double trace_dt,
                                    const Sink& sink) {
  if (!(segment.duration > 0.0)) return;
  const double n_steps = std::max(1.0, std::ceil(segment.duration / max_step_ - 1e-9));
  const double h = segment.duration / n_steps;
  const Matrix& phi = transition(h);
  const long n = static_cast<long>(n_steps);

  const int states = c_.states;
  Vector z{};
  for (int i = 0; i < states; ++i) z[static_cast<std::size_t>(aug(i))] = y[i];
  z[kVc] = segment.v0;
  z[kAc] = segment.a0;
  z[kJerk] = segment.jerk;
  double next_grid = trace_dt > 0.0 ? (std::floor(segment.start_time / trace_dt) + 1.0) * trace_dt
                                    : segment.end_time() + 1.0;

  struct Interior {
    double t;
    double s;
  };
  std::array<Interior, 64> interior{};
  for (long k = 0; k < n; ++k) {
    const double t0 = segment.start_time + static_cast<double>(k) * h;
    const double t1 = k + 1 == n ? segment.end_time() : t0 + h;
    // The Coulomb fraction as a line over the step: its value and its rate at the step start.
    const double v_h = z[kHoseVelocity];
    const double f = coulomb_fraction(c_, v_h);
    z[kF0] = f;
    z[kF1] = (1.0 - f * f) * c_.inv_coulomb_speed * (z[kHoseInner] - v_h) * c_.inv_tau;
    const Vector z0 = z;
    z = apply(phi, z0, n_);
    ++steps_;

    // Interior samples: an extremum of the tip error (de/dt = −φ η̇ − ψ η̇₂ changes sign) and
    // the trace grid. Without a second mode the tip error is −φ η: η's extrema, as they were.
    std::size_t count = 0;
    double p0 = z0[kMode];
    double d0 = z0[kModeRate];
    double p1 = z[kMode];
    double d1 = z[kModeRate];
    if (c_.has_mode2) {
      constexpr auto kM2 = static_cast<std::size_t>(aug(kMode2));
      constexpr auto kR2 = static_cast<std::size_t>(aug(kMode2Rate));
      p0 = c_.phi * z0[kMode] + c_.psi * z0[kM2];
      d0 = c_.phi * z0[kModeRate] + c_.psi * z0[kR2];
      p1 = c_.phi * z[kMode] + c_.psi * z[kM2];
      d1 = c_.phi * z[kModeRate] + c_.psi * z[kR2];
    }
    if ((d0 > 0.0 && d1 < 0.0) || (d0 < 0.0 && d1 > 0.0)) {
      const double s = hermite_stationary_point(h, p0, d0, p1, d1);
      if (s > 0.0 && s < 1.0) {
        interior[count++] = {t0 + s * h, s};
        ++extrema_;
      }
    }
    while (next_grid < t1 - 1e-9 * h && count < interior.size()) {
      if (next_grid > t0 + 1e-9 * h) interior[count++] = {next_grid, (next_grid - t0) / h};
      next_grid += trace_dt;
    }
    if (count > 0) {
      std::sort(interior.begin(),
                interior.begin() + static_cast<std::ptrdiff_t>(count),
                [](const Interior& a, const Interior& b) { return a.t < b.t; });
      // Every state by cubic Hermite from the exact values and rates at both ends.
      double y0[kStates] = {};
      double y1[kStates] = {};
      for (int j = 0; j < states; ++j) {
        y0[j] = z0[static_cast<std::size_t>(aug(j))];
        y1[j] = z[static_cast<std::size_t>(aug(j))];
      }
      double dy0[kStates] = {};
      double dy1[kStates] = {};
      const motion::MotionState cmd0{0.0, z0[kVc], z0[kAc], z0[kJerk]};
      const motion::MotionState cmd1{0.0, z[kVc], z[kAc], z[kJerk]};
      derivatives(c_, cmd0, y0, dy0);
      derivatives(c_, cmd1, y1, dy1);
      for (std::size_t i = 0; i < count; ++i) {
        // In floating point t0 + s·h can round onto the step's ends or onto another sample.
        if (!(interior[i].t > last_time_ && interior[i].t < t1)) continue;
        double yi[kStates] = {};
        for (int j = 0; j < states; ++j) {
          yi[j] = hermite(interior[i].s, h, y0[j], dy0[j], y1[j], dy1[j]);
        }
        last_time_ = interior[i].t;
        sink(interior[i].t, yi);
      }
    }
    for (int i = 0; i < states; ++i) y[i] = z[static_cast<std::size_t>(aug(i))];
    if (t1 > last_time_) {
      last_time_ = t1;
      sink(t1, y);
    }
  }
}

}  // namespace cmmcomp::dynamics
