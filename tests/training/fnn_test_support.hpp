// SPDX-License-Identifier: MIT
/// @file Data and helpers shared by the trainer's stage tests (tests/training/test_fnn_*.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/detail/splitmix64.hpp>
#include <cmmcomp/doe/designs.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cstring>
#include <functional>
#include <string>
#include <vector>

namespace cmmcomp::training::fnn_test {

/// Portable generator for test data: the project's one (detail/splitmix64.hpp).
using Rng = cmmcomp::detail::SplitMix64;

template <std::size_t N>
using Rows = std::vector<std::array<double, N>>;

/// Raw input ranges used by the synthetic data (PV mm/s, PD mm, AV mm/s, AD mm).
constexpr std::array<std::array<double, 2>, 4> kRanges{{{20, 120}, {10, 300}, {1, 10}, {0.5, 3}}};

/// The paper's Table 3 ranges in the design's units (doe::paper_table3_factors(): SI).
inline std::array<double, 4> paper_range(bool high) {
  const doe::Design l18 = doe::paper_l18_design();
  std::array<double, 4> out{};
  for (std::size_t i = 0; i < 4; ++i) {
    out[i] = l18.values[0][i];
    for (const auto& run : l18.values)
      out[i] = high ? std::max(out[i], run[i]) : std::min(out[i], run[i]);
  }
  return out;
}

/// A smooth nonlinear function of the four normalised inputs (µm-sized).
inline double smooth4(const std::array<double, 4>& u) {
  return 8.0 + 6.0 * u[0] - 4.0 * u[1] * u[1] + 3.0 * std::sin(3.0 * u[2]) * u[3] +
         2.0 * u[0] * u[1];
}

/// n random samples of 4 inputs in kRanges; `u` receives the normalised values.
inline Rows<4> random_inputs4(Rng& rng, std::size_t n, Rows<4>* u) {
  Rows<4> x(n);
  if (u != nullptr) u->resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    for (std::size_t i = 0; i < 4; ++i) {
      const double v = rng.uniform();
      x[k][i] = kRanges[i][0] + v * (kRanges[i][1] - kRanges[i][0]);
      if (u != nullptr) (*u)[k][i] = v;
    }
  }
  return x;
}

inline double rms(const std::vector<double>& e) {
  double s = 0;
  for (double v : e) s += v * v;
  return std::sqrt(s / static_cast<double>(e.size()));
}

inline Rows<2> line_inputs(int n) {
  Rows<2> x;
  for (int k = 0; k < n; ++k) x.push_back({static_cast<double>(k), static_cast<double>(k * k)});
  return x;
}

inline std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "no ConfigError";
}

/// The paper's L18 × `repeats` in raw units (PV, PD, AV, AD at their Table 3 levels).
inline Rows<4> paper_l18_inputs(int repeats) {
  const doe::Design l18 = doe::replicate(doe::paper_l18_design(), repeats);
  Rows<4> x;
  for (const auto& run : l18.values) x.push_back({run[0], run[1], run[2], run[3]});
  return x;
}

/// A response of PV and PD only that bends along a diagonal of their square, like the twin's RPE
/// along the triangular boundary (u: inputs normalised over the Table 3 ranges).
inline double bent2(const std::array<double, 4>& u) {
  return 6.0 + 4.0 * u[0] + 6.0 / (1.0 + 4.0 * (u[1] - u[0] + 1.0));
}

inline std::array<double, 4> normalised_on(const Rows<4>& x, const std::array<double, 4>& v) {
  std::array<double, 4> u{};
  for (std::size_t i = 0; i < 4; ++i) {
    double lo = x[0][i], hi = lo;
    for (const auto& r : x) {
      lo = std::min(lo, r[i]);
      hi = std::max(hi, r[i]);
    }
    u[i] = (v[i] - lo) / (hi - lo);
  }
  return u;
}

template <int kI, int kS, int kO>
bool bit_identical(const fuzzy::TskModel<double, kI, kS, kO>& a,
                   const fuzzy::TskModel<double, kI, kS, kO>& b) {
  return std::memcmp(a.params.values.data(), b.params.values.data(), sizeof(a.params.values)) == 0;
}

}  // namespace cmmcomp::training::fnn_test
