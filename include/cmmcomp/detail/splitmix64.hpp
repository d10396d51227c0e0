// SPDX-License-Identifier: MIT
/// @file SplitMix64: the project's portable random generator for noise, training and tests (not
/// API). The one other, std::mt19937_64 in doe::latin_hypercube, is used only through its raw
/// output, whose sequence the C++ standard specifies, so it is as portable; it stays because the
/// shipped datasets, models and figures were drawn with it.
///
/// Steele, Lea & Flood 2014, with the constants of Vigna's reference code. Every draw is made
/// from its raw 64-bit output, never through std:: distributions (whose results differ between
/// standard libraries), so seeded results are bit-identical on every platform.
#pragma once

#include <cmath>
#include <cstdint>
#include <limits>

namespace cmmcomp::detail {

struct SplitMix64 {
  std::uint64_t state;

  std::uint64_t next() noexcept {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in [0, 1) from the top 53 bits.
  double uniform() noexcept { return static_cast<double>(next() >> 11) * 0x1.0p-53; }
  /// Uniform in [lo, hi).
  double uniform(double lo, double hi) noexcept { return lo + (hi - lo) * uniform(); }
  /// Uniform in (0, 1): never 0, so its logarithm is finite.
  double uniform_open() noexcept {
    return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  }
  /// Uniform integer in [0, n), n > 0, by rejection (no modulo bias).
  std::uint64_t below(std::uint64_t n) noexcept {
    const std::uint64_t limit =
        std::numeric_limits<std::uint64_t>::max() - std::numeric_limits<std::uint64_t>::max() % n;
    std::uint64_t v = next();
    while (v >= limit) v = next();
    return v % n;
  }
  /// Standard normal by Box–Muller (one of the pair).
  double normal() noexcept {
    const double u1 = uniform_open();
    const double u2 = uniform_open();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
};

}  // namespace cmmcomp::detail
