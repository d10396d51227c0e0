// SPDX-License-Identifier: MIT
/// @file exp(v) for v <= 0, written so that a compiler can vectorise it (the memberships of the
/// T-S network's real-time evaluator).
///
/// Why not std::exp: a call to libm cannot be vectorised without -ffast-math (and glibc's
/// vector variants are then only 4-ulp accurate), and the 12 memberships of the paper's network
/// were a third of the evaluator's time as 12 scalar calls. This is plain IEEE arithmetic with
/// no branch and no table, so a loop of it becomes SIMD code, and it computes the same bits in
/// scalar, SSE2, AVX2 or AVX-512 code, as long as the compiler does not contract a·b + c into
/// a fused multiply-add (cmmcomp::core sets -ffp-contract=off for its users; see CMakeLists).
///
/// Method (Cody and Waite): v = k·ln2 + r with k = round(v/ln2) and |r| <= ln2/2, the product
/// k·ln2 split into an exact high part and a low correction; exp(r) by its Taylor series
/// evaluated with Estrin's scheme (short dependency chains); 2^k built in the exponent field.
/// The argument is the shifted exponent of a Gaussian membership, never positive; below the
/// smallest normal result the function returns exactly 0 (no subnormals).
///
/// Accuracy (tests/fuzzy/test_exp_nonpositive.cpp): within 2 ulp of correctly rounded std::exp
/// for v in [-708, 0] (double) and [-87, 0] (float); exactly 1 at 0; 0 below.
///
/// Under -ffast-math the compiler may re-associate (t + 2^52·1.5) − 2^52·1.5 into t and break
/// the rounding step, so such builds use std::exp instead.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

namespace cmmcomp::fuzzy {

namespace detail {

/// The IEEE-754 binary layout of Float: an integer of the same size, the significand's width
/// and the exponent bias.
template <typename Float>
struct FloatBits;
template <>
struct FloatBits<double> {
  using Int = std::int64_t;
  static constexpr int kSignificandBits = 52;
  static constexpr Int kBias = 1023;
};
template <>
struct FloatBits<float> {
  using Int = std::int32_t;
  static constexpr int kSignificandBits = 23;
  static constexpr Int kBias = 127;
};

/// p·2^k, where t = round + k came out of the rounding step (round = 1.5·2^significand_bits, so
/// k is the low bits of t's significand): k + bias is written into the exponent field of the
/// scale. Precondition: k + bias in [1, 2·bias] (a normal scale).
template <typename Float>
inline Float times_power_of_two(Float p, Float t, Float round) noexcept {
  using Bits = FloatBits<Float>;
  typename Bits::Int t_bits = 0;
  typename Bits::Int round_bits = 0;
  std::memcpy(&t_bits, &t, sizeof t);
  std::memcpy(&round_bits, &round, sizeof round);
  const typename Bits::Int scale_bits = (t_bits - round_bits + Bits::kBias)
                                        << Bits::kSignificandBits;
  Float scale = 0;
  std::memcpy(&scale, &scale_bits, sizeof scale);
  return p * scale;
}

}  // namespace detail

/// exp(v) for v <= 0 (and v = -0): the double result within 2 ulp, 0 for v < -708 (where
/// exp(v) < 3.3e-308, below the smallest normal double). RT-safe, branch-free. NaN is not an
/// accepted input (the evaluator never passes one).
inline double exp_nonpositive(double v) noexcept {
#if defined(__FAST_MATH__)
  return v > -708.0 ? std::exp(v) : 0.0;
#else
  constexpr double kLog2e = 1.4426950408889634;
  constexpr double kLn2Hi = 6.93147180369123816490e-01;  // 32 significant bits: k·kLn2Hi exact
  constexpr double kLn2Lo = 1.90821492927058770002e-10;  // ln2 − kLn2Hi
  constexpr double kRound = 6755399441055744.0;          // 1.5·2^52: adding it rounds to integer
  constexpr double kLowest = -708.0;
  const double vc = v > kLowest ? v : kLowest;
  const double t = vc * kLog2e + kRound;  // kRound + k, k = round(v/ln2) in [-1022, 0]
  const double k = t - kRound;
  const double r = (vc - k * kLn2Hi) - k * kLn2Lo;  // |r| <= ln2/2
  // Σ_{n=0}^{13} r^n/n! (truncation < 5e-18 relative), Estrin: pairs, then r², r⁴, r⁸.
  const double r2 = r * r;
  const double r4 = r2 * r2;
  const double r8 = r4 * r4;
  const double q0 = 1.0 + r;
  const double q1 = 1.0 / 2 + r * (1.0 / 6);
  const double q2 = 1.0 / 24 + r * (1.0 / 120);
  const double q3 = 1.0 / 720 + r * (1.0 / 5040);
  const double q4 = 1.0 / 40320 + r * (1.0 / 362880);
  const double q5 = 1.0 / 3628800 + r * (1.0 / 39916800);
  const double q6 = 1.0 / 479001600 + r * (1.0 / 6227020800.0);
  const double u0 = q0 + q1 * r2;
  const double u1 = q2 + q3 * r2;
  const double u2 = q4 + q5 * r2;
  const double w0 = u0 + u1 * r4;
  const double w1 = u2 + q6 * r4;
  const double p = w0 + w1 * r8;
  return v > kLowest ? detail::times_power_of_two(p, t, kRound) : 0.0;
#endif
}

/// exp(v) for v <= 0 in float: within 2 ulp, 0 for v < -87 (exp(-87) = 1.6e-38, just above
/// the smallest normal float). RT-safe, branch-free.
inline float exp_nonpositive(float v) noexcept {
#if defined(__FAST_MATH__)
  return v > -87.0f ? std::exp(v) : 0.0f;
#else
  constexpr float kLog2e = 1.44269504f;
  constexpr float kLn2Hi = 0.693359375f;     // 9 significant bits: k·kLn2Hi exact
  constexpr float kLn2Lo = -2.12194440e-4f;  // ln2 − kLn2Hi
  constexpr float kRound = 12582912.0f;      // 1.5·2^23
  constexpr float kLowest = -87.0f;
  const float vc = v > kLowest ? v : kLowest;
  const float t = vc * kLog2e + kRound;
  const float k = t - kRound;
  const float r = (vc - k * kLn2Hi) - k * kLn2Lo;
  // Σ_{n=0}^{7} r^n/n! (truncation < 6e-9 relative), Estrin.
  const float r2 = r * r;
  const float r4 = r2 * r2;
  const float q0 = 1.0f + r;
  const float q1 = 1.0f / 2 + r * (1.0f / 6);
  const float q2 = 1.0f / 24 + r * (1.0f / 120);
  const float q3 = 1.0f / 720 + r * (1.0f / 5040);
  const float p = (q0 + q1 * r2) + (q2 + q3 * r2) * r4;
  return v > kLowest ? detail::times_power_of_two(p, t, kRound) : 0.0f;
#endif
}

}  // namespace cmmcomp::fuzzy
