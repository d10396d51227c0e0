// SPDX-License-Identifier: MIT
/// @file Reproducible measurement noise on the four dynamic errors (the laser tracker's scatter).
#pragma once

#include <cmath>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cstdint>

namespace cmmcomp::dynamics {

/// Gaussian noise added to each parameter of a simulated move. The default standard deviations
/// are the paper's Table 1 (five repeats at the baseline). Noise for sample i depends only on
/// (seed, i), never on thread count or order.
struct MeasurementNoise {
  bool enabled = false;         ///< off: parameters are returned as simulated
  double mpe_sigma_um = 1.321;  ///< standard deviation on MPE [µm]
  double rpe_sigma_um = 0.461;  ///< on RPE [µm]
  double mae_sigma_um = 0.612;  ///< on MAE [µm]
  double rae_sigma_um = 0.304;  ///< on RAE [µm]
  std::uint64_t seed = 1;       ///< stream seed
};

namespace detail {

/// SplitMix64: a tiny, well-mixed generator whose output is identical on every platform
/// (std:: distributions are not).
struct SplitMix64 {
  std::uint64_t state;
  std::uint64_t next() noexcept {
    std::uint64_t z = (state += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
  }
  /// Uniform in (0, 1), never 0.
  double uniform() noexcept {
    return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0);
  }
  /// Standard normal by Box–Muller (one of the pair).
  double normal() noexcept {
    const double u1 = uniform();
    const double u2 = uniform();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
};

}  // namespace detail

/// `clean` (µm) plus the noise of sample `index`. MPE and MAE stay magnitudes (never below 0).
inline errors::DynamicErrors add_noise(const errors::DynamicErrors& clean,
                                       const MeasurementNoise& noise,
                                       std::uint64_t index) noexcept {
  if (!noise.enabled) return clean;
  detail::SplitMix64 rng{noise.seed * 0x9e3779b97f4a7c15ULL ^ (index + 0x632be59bd9b4e019ULL)};
  rng.next();
  errors::DynamicErrors e = clean;
  e.mpe = std::fabs(e.mpe + noise.mpe_sigma_um * rng.normal());
  e.rpe += noise.rpe_sigma_um * rng.normal();
  e.mae = std::fabs(e.mae + noise.mae_sigma_um * rng.normal());
  e.rae += noise.rae_sigma_um * rng.normal();
  return e;
}

}  // namespace cmmcomp::dynamics
