// SPDX-License-Identifier: MIT
/// @file Gaussian membership functions and input normalisation of the T-S network (layer 2).
///
/// Everything here is templated on `Scalar` and uses only operations `ceres::Jet` supports
/// (`exp`, `+ - * /`, comparisons), so training differentiates the very code the RT path runs.
/// No Ceres header is included: `exp` is found by argument-dependent lookup for Jet.
#pragma once

#include <cmath>
#include <cmmcomp/fuzzy/exp_nonpositive.hpp>
#include <type_traits>

namespace cmmcomp::fuzzy {

/// Training range of one input: the model maps [lo, hi] onto [0, 1]. In that input's own unit
/// (the model file's `inputs[i].unit`: mm/s or mm for cmmcomp-train's models).
struct InputRange {
  double lo = 0.0;  ///< lower end of the training range
  double hi = 1.0;  ///< upper end of the training range; must be > lo
};

/// Normalised input (x − lo)/(hi − lo): 0 at `lo`, 1 at `hi`, linear beyond. RT-safe.
/// Precondition: lo < hi, both finite (checked by `validate` at model publication).
constexpr double normalise(double x, const InputRange& range) noexcept {
  return (x - range.lo) / (range.hi - range.lo);
}

/// Normalised distances |x − c|/σ are saturated at this value before squaring, so that the
/// exponent −d² stays finite in float, double and Jet (1e36 < FLT_MAX) even for absurd inputs
/// or widths. Where it applies the membership is exp(−1e36) = 0 in every type anyway.
inline constexpr double kMaxNormalisedDistance = 1e18;

namespace detail {

/// max(a, b) for any Scalar with `<` (std::max is not used: it does not exist for Jet).
template <typename Scalar>
constexpr const Scalar& max_of(const Scalar& a, const Scalar& b) noexcept {
  return a < b ? b : a;
}

/// min(a, b) for any Scalar with `<`.
template <typename Scalar>
constexpr const Scalar& min_of(const Scalar& a, const Scalar& b) noexcept {
  return b < a ? b : a;
}

/// `v` limited to [lo, hi] (lo <= hi). For Jet the derivative is zero where it clamps.
template <typename Scalar>
constexpr Scalar clamp_of(const Scalar& v, const Scalar& lo, const Scalar& hi) noexcept {
  return min_of(max_of(v, lo), hi);
}

}  // namespace detail

/// Exponent of the Gaussian membership, −((x − c)/σ)², with |x − c|/σ saturated at
/// kMaxNormalisedDistance (finite for any finite or infinite x and any σ > 0). RT-safe.
template <typename Scalar>
Scalar gaussian_exponent(const Scalar& x, const Scalar& centre, const Scalar& width) noexcept {
  const Scalar bound = static_cast<Scalar>(kMaxNormalisedDistance);
  const Scalar d = detail::clamp_of(Scalar((x - centre) / width), Scalar(-bound), bound);
  return -(d * d);
}

/// The same exponent from the reciprocal width 1/σ: −((x − c)·(1/σ))², saturated alike. The
/// evaluator's form (a multiply instead of a divide on the input's path). RT-safe.
template <typename Scalar>
Scalar gaussian_exponent_scaled(const Scalar& x,
                                const Scalar& centre,
                                const Scalar& inv_width) noexcept {
  const Scalar bound = static_cast<Scalar>(kMaxNormalisedDistance);
  const Scalar d = detail::clamp_of(Scalar((x - centre) * inv_width), Scalar(-bound), bound);
  return -(d * d);
}

/// exp(v) for a membership exponent v <= 0: exp_nonpositive (vectorisable, same bits on every
/// SIMD width) for double and float, the Scalar's own `exp` (found by ADL) for ceres::Jet,
/// whose derivative part the RT path never needs. RT-safe for double and float.
template <typename Scalar>
Scalar membership_exp(const Scalar& v) noexcept {
  if constexpr (std::is_floating_point_v<Scalar>) {
    return exp_nonpositive(v);
  } else {
    using std::exp;
    return exp(v);
  }
}

/// Gaussian membership μ = exp(−(x − c)²/σ²) (Wei et al. 2019, §4, layer 2). RT-safe.
/// σ (`width`) is not a standard deviation: this shape has standard deviation σ/√2, so a
/// library that takes one (fuzzylite's Gaussian) needs σ/√2 for the same function.
/// Precondition: σ > 0. The evaluator computes the memberships of all inputs together and
/// shifts them per input (TskEvaluator::memberships); this is the definition they follow.
template <typename Scalar>
Scalar gaussian_membership(const Scalar& x, const Scalar& centre, const Scalar& width) noexcept {
  return membership_exp(gaussian_exponent(x, centre, width));
}

}  // namespace cmmcomp::fuzzy
