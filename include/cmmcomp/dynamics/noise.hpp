// SPDX-License-Identifier: MIT
/// @file Reproducible measurement noise on the four dynamic errors (the laser tracker's scatter).
#pragma once

#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/errors/dynamic_errors.hpp>
#include <cmmcomp/paper_reference.hpp>
#include <cstdint>

namespace cmmcomp::dynamics {

/// Gaussian noise added to each parameter of a simulated move. The default standard deviations
/// are the paper's Table 1 (five repeats at the baseline). Noise for sample i depends only on
/// (seed, i), never on thread count or order.
struct MeasurementNoise {
  bool enabled = false;                        ///< off: parameters are returned as simulated
  double mpe_sigma_um = paper::kTable1Std[0];  ///< standard deviation on MPE [µm]
  double rpe_sigma_um = paper::kTable1Std[1];  ///< on RPE [µm]
  double mae_sigma_um = paper::kTable1Std[2];  ///< on MAE [µm]
  double rae_sigma_um = paper::kTable1Std[3];  ///< on RAE [µm]
  std::uint64_t seed = 1;                      ///< stream seed
};

/// `clean` (µm) plus the noise of sample `index`. MPE and MAE stay magnitudes (never below 0).
inline errors::DynamicErrors add_noise(const errors::DynamicErrors& clean,
                                       const MeasurementNoise& noise,
                                       std::uint64_t index) noexcept {
  if (!noise.enabled) return clean;
  cmmcomp::detail::SplitMix64 rng{noise.seed * 0x9e3779b97f4a7c15ULL ^
                                  (index + 0x632be59bd9b4e019ULL)};
  rng.next();
  errors::DynamicErrors e = clean;
  e.mpe = std::fabs(e.mpe + noise.mpe_sigma_um * rng.normal());
  e.rpe += noise.rpe_sigma_um * rng.normal();
  e.mae = std::fabs(e.mae + noise.mae_sigma_um * rng.normal());
  e.rae += noise.rae_sigma_um * rng.normal();
  return e;
}

}  // namespace cmmcomp::dynamics
