// SPDX-License-Identifier: MIT
/// @file The calibrated prediction interval of a network's outputs (docs/uncertainty.md).
///
/// For each output o the half-width of the interval that holds the measured value with
/// probability `coverage` (0.95: U95) is
///
///     U_o(x) = half_width_o · (1 + corner_gain_o · κ(x) + extrapolation_gain_o · d(x))
///
/// where d(x) is the Euclidean distance of the raw input x from the training box, each input in
/// units of its own training range (0 inside the box), and κ(x) = (mean_i (2·u_i − 1)²)² its
/// corner share, u_i the input's place in its range clamped to [0, 1]: 0 at the box's centre,
/// about 0.13 on average over uniformly drawn moves (1/9 + 4/(45·n) for n inputs), 1 at a
/// corner, where a fitted model is least sure.
/// `half_width` and `corner_gain` are a locally weighted split-conformal calibration on the
/// cross-validated residuals r of the training data: corner_gain from the least-squares line
/// |r| ≈ a·(1 + corner_gain·κ), half_width the coverage quantile of |r| / (1 + corner_gain·κ)
/// (in the output's unit); `extrapolation_gain` comes from residuals of models trained with one
/// end of one input left out (training/fnn_trainer.hpp, step 7). The distance is taken from the
/// input as the move gives it, before any clamping, so a clamped prediction outside the domain also
/// gets a wider interval: clamping keeps the prediction bounded, not right.
///
/// RT-safe: no allocation, no exception, 2·kInputs + 2·kOutputs multiply-adds and one sqrt; never
/// NaN for finite inputs (validate_interval is checked at publication).
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/membership.hpp>
#include <cstddef>
#include <string>

namespace cmmcomp::fuzzy {

/// The interval calibration of a model with `kOutputs` outputs. `coverage` = 0 means "no
/// calibration" (a model file of format version 1, or a model built in code): the interval is
/// then unknown, never zero by accident.
template <int kOutputs>
struct IntervalCalibration {
  double coverage = 0.0;  ///< nominal coverage in (0, 1); 0: none
  /// In-domain half-width of each output [output units], >= 0.
  std::array<double, static_cast<std::size_t>(kOutputs)> half_width{};
  /// Growth of the half-width per training range outside the box, >= 0.
  std::array<double, static_cast<std::size_t>(kOutputs)> extrapolation_gain{};
  /// Growth of the half-width at the box's corners (κ = 1), >= 0. 0 in a model file of format
  /// version 2, which had none.
  std::array<double, static_cast<std::size_t>(kOutputs)> corner_gain{};

  /// True when the model carries a calibration.
  constexpr bool available() const noexcept { return coverage > 0.0; }

  constexpr bool operator==(const IntervalCalibration& o) const noexcept {
    bool same = coverage == o.coverage;
    for (std::size_t k = 0; k < half_width.size(); ++k) {
      same = same && half_width[k] == o.half_width[k] &&
             extrapolation_gain[k] == o.extrapolation_gain[k] && corner_gain[k] == o.corner_gain[k];
    }
    return same;
  }
  constexpr bool operator!=(const IntervalCalibration& o) const noexcept { return !(*this == o); }
};

/// Each input's excess over its training box counts at most this many training ranges, so the
/// distance and the interval stay finite for any finite input (an input 1e200 ranges out would
/// otherwise overflow the sum of squares to inf, and 0 · inf to NaN where a gain is 0).
inline constexpr double kMaxRangesOutside = 1e6;
/// The largest half-width reported [output units]: a bound far above any physical error, so a
/// huge gain times a capped distance cannot overflow either.
inline constexpr double kMaxHalfWidth = 1e12;

/// Distance of the raw input `x` from the box of `ranges`, each input in units of its range
/// (hi − lo), each excess capped at kMaxRangesOutside:
/// sqrt(Σ_i min(max(lo_i − x_i, x_i − hi_i, 0)/(hi_i − lo_i), kMaxRangesOutside)²); 0 inside.
/// RT-safe. Precondition: every range valid (lo < hi, finite) and x finite.
template <std::size_t kInputs>
inline double domain_distance(const std::array<InputRange, kInputs>& ranges,
                              const std::array<double, kInputs>& x) noexcept {
  double sum = 0.0;
  for (std::size_t i = 0; i < kInputs; ++i) {
    const InputRange& r = ranges[i];
    const double below = r.lo - x[i];
    const double above = x[i] - r.hi;
    const double excess = below > 0.0 ? below : (above > 0.0 ? above : 0.0);
    const double ranges_out = excess / (r.hi - r.lo);
    const double e = ranges_out < kMaxRangesOutside ? ranges_out : kMaxRangesOutside;
    sum += e * e;
  }
  return std::sqrt(sum);
}

/// Corner share κ of the raw input `x` in the box of `ranges`: (mean_i (2·u_i − 1)²)² with u_i
/// = (x_i − lo_i)/(hi_i − lo_i) clamped to [0, 1]; in [0, 1], 1 at (and beyond) a corner.
/// RT-safe. Precondition as domain_distance.
template <std::size_t kInputs>
inline double corner_share(const std::array<InputRange, kInputs>& ranges,
                           const std::array<double, kInputs>& x) noexcept {
  double sum = 0.0;
  for (std::size_t i = 0; i < kInputs; ++i) {
    const InputRange& r = ranges[i];
    const double u = (x[i] - r.lo) / (r.hi - r.lo);
    const double c = u < 0.0 ? -1.0 : (u > 1.0 ? 1.0 : 2.0 * u - 1.0);
    sum += c * c;
  }
  const double m = sum / static_cast<double>(kInputs);
  return m * m;
}

/// The half-widths U_o at a move whose input lies `distance` (domain_distance) from the
/// training box with corner share `corner` (corner_share). Writes 0 everywhere when `cal` is not
/// available. RT-safe.
template <int kOutputs>
inline void interval_half_widths(
    const IntervalCalibration<kOutputs>& cal,
    double distance,
    double corner,
    std::array<double, static_cast<std::size_t>(kOutputs)>& u) noexcept {
  for (std::size_t o = 0; o < u.size(); ++o) {
    const double w = cal.available() ? cal.half_width[o] * (1.0 + cal.corner_gain[o] * corner +
                                                            cal.extrapolation_gain[o] * distance)
                                     : 0.0;
    u[o] = w < kMaxHalfWidth ? w : kMaxHalfWidth;  // also maps an overflow to the bound
  }
}

/// The half-widths U_o of the raw input `x` of a model with training box `ranges`. RT-safe.
template <int kOutputs, std::size_t kInputs>
inline void interval_half_widths_at(
    const IntervalCalibration<kOutputs>& cal,
    const std::array<InputRange, kInputs>& ranges,
    const std::array<double, kInputs>& x,
    std::array<double, static_cast<std::size_t>(kOutputs)>& u) noexcept {
  interval_half_widths(cal, domain_distance(ranges, x), corner_share(ranges, x), u);
}

/// True when `cal` may be published (validate_interval's rule, without the message). RT-safe,
/// for firmware that checks a calibration before publishing it.
template <int kOutputs>
constexpr bool interval_is_valid(const IntervalCalibration<kOutputs>& cal) noexcept {
  bool good = cal.coverage >= 0.0 && cal.coverage < 1.0;
  for (std::size_t o = 0; o < cal.half_width.size(); ++o) {
    const double h = cal.half_width[o];
    const double g = cal.extrapolation_gain[o];
    const double k = cal.corner_gain[o];
    // v − v is 0 exactly when v is finite (constexpr, unlike std::isfinite in C++17).
    good = good && (h - h) == 0.0 && h >= 0.0 && (g - g) == 0.0 && g >= 0.0;
    good = good && (k - k) == 0.0 && k >= 0.0;
    good = good && (cal.available() || (h == 0.0 && g == 0.0 && k == 0.0));
  }
  return good;
}

/// True when `cal` may be published: coverage 0 (none) with every value 0, or coverage in
/// (0, 1) with every half-width and gain finite and >= 0. Otherwise false and, if `why` is
/// given, the first problem. Setup only.
template <int kOutputs>
bool validate_interval(const IntervalCalibration<kOutputs>& cal, std::string* why = nullptr) {
  const auto fail = [why](const std::string& what) {
    if (why != nullptr) *why = what;
    return false;
  };
  if (!(cal.coverage >= 0.0 && cal.coverage < 1.0)) {
    return fail("interval coverage is not in [0, 1)");
  }
  for (std::size_t o = 0; o < cal.half_width.size(); ++o) {
    const double h = cal.half_width[o];
    const double g = cal.extrapolation_gain[o];
    if (!(std::isfinite(h) && h >= 0.0)) {
      return fail("interval half-width of output " + std::to_string(o) + " is not finite and >= 0");
    }
    if (!(std::isfinite(g) && g >= 0.0)) {
      return fail("interval extrapolation gain of output " + std::to_string(o) +
                  " is not finite and >= 0");
    }
    const double k = cal.corner_gain[o];
    if (!(std::isfinite(k) && k >= 0.0)) {
      return fail("interval corner gain of output " + std::to_string(o) +
                  " is not finite and >= 0");
    }
    if (!cal.available() && (h != 0.0 || g != 0.0 || k != 0.0)) {
      return fail("interval values without a coverage (coverage 0 means no calibration)");
    }
  }
  return true;
}

}  // namespace cmmcomp::fuzzy
