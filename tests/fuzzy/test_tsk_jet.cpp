// SPDX-License-Identifier: MIT
/// @file The T-S evaluator with ceres::Jet: explicit instantiation, values equal to double, and
/// derivatives w.r.t. parameters and inputs against central finite differences.
#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <random>

#include "support/test_seed.hpp"

// Every member compiles for Jet (the training path differentiates this very code).
template class cmmcomp::fuzzy::TskEvaluator<ceres::Jet<double, 8>, 4, 3, 1>;
template class cmmcomp::fuzzy::TskEvaluator<ceres::Jet<double, 8>, 4, 3, 4>;
template class cmmcomp::fuzzy::TskEvaluator<ceres::Jet<double, 3>, 1, 2, 1>;
template struct cmmcomp::fuzzy::TskParams<ceres::Jet<double, 8>, 4, 3, 4>;
template struct cmmcomp::fuzzy::TskModel<ceres::Jet<double, 8>, 4, 3, 4>;

namespace cmmcomp::fuzzy {
namespace {

constexpr int kChunk = 8;  // derivatives per pass, as Ceres evaluates large blocks in chunks
using Jet = ceres::Jet<double, kChunk>;
using EvalD = TskEvaluator<double, 4, 3, 2>;
using EvalJ = TskEvaluator<Jet, 4, 3, 2>;

std::array<double, EvalD::kParamCount> random_params(std::mt19937_64& rng) {
  using Layout = EvalD::Layout;
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_real_distribution<double> width(0.2, 0.6);
  std::uniform_real_distribution<double> coef(-1.0, 1.0);
  std::array<double, EvalD::kParamCount> p{};
  for (int k = 0; k < EvalD::kParamCount; ++k) {
    const bool is_width = k >= Layout::kWidthsOffset && k < Layout::kConsequentsOffset;
    const bool is_centre = k < Layout::kWidthsOffset;
    p[static_cast<unsigned>(k)] = is_width ? width(rng) : (is_centre ? unit(rng) : coef(rng));
  }
  return p;
}

// |jet - fd| <= kAbsTol + kRelTol * |fd|: central differences with h = 1e-6 have truncation
// error ~h^2 |f'''| and rounding error ~1e-16/h, both far below these.
constexpr double kAbsTol = 1e-7;
constexpr double kRelTol = 1e-6;
constexpr double kStep = 1e-6;

// Jet divides as a * (1/b), so values agree with double to rounding, not bit for bit.
constexpr double kValueTol = 1e-14;

TEST(TskEvaluatorJet, ValuesEqualTheDoubleEvaluation) {
  std::mt19937_64 rng(test::seed());
  const auto p = random_params(rng);
  const EvalD::Input x{0.2, 0.7, 0.45, 0.9};
  EvalD::Output y{};
  EvalD::forward(p.data(), x, y);
  std::array<Jet, EvalD::kParamCount> pj;
  for (std::size_t k = 0; k < p.size(); ++k) pj[k] = Jet(p[k]);
  EvalJ::Input xj;
  for (std::size_t i = 0; i < 4; ++i) xj[i] = Jet(x[i]);
  EvalJ::Output yj;
  EvalJ::forward(pj.data(), xj, yj);
  for (std::size_t o = 0; o < 2; ++o) {
    EXPECT_NEAR(yj[o].a, y[o], kValueTol);
    EXPECT_EQ(yj[o].v.norm(), 0.0);
  }
}

TEST(TskEvaluatorJet, ParameterGradientMatchesCentralDifferences) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 1);
  std::uniform_real_distribution<double> unit(-0.1, 1.1);  // a little outside [0, 1] too
  for (int c = 0; c < 3; ++c) {
    const auto p = random_params(rng);
    const EvalD::Input x{unit(rng), unit(rng), unit(rng), unit(rng)};
    EvalJ::Input xj;
    for (std::size_t i = 0; i < 4; ++i) xj[i] = Jet(x[i]);
    for (int first = 0; first < EvalD::kParamCount; first += kChunk) {
      std::array<Jet, EvalD::kParamCount> pj;
      for (int k = 0; k < EvalD::kParamCount; ++k) {
        const unsigned u = static_cast<unsigned>(k);
        pj[u] = (k >= first && k < first + kChunk) ? Jet(p[u], k - first) : Jet(p[u]);
      }
      EvalJ::Output yj;
      EvalJ::forward(pj.data(), xj, yj);
      for (int k = first; k < std::min(first + kChunk, EvalD::kParamCount); ++k) {
        auto plus = p;
        auto minus = p;
        const double h = kStep * std::max(1.0, std::fabs(p[static_cast<unsigned>(k)]));
        plus[static_cast<unsigned>(k)] += h;
        minus[static_cast<unsigned>(k)] -= h;
        EvalD::Output yp{};
        EvalD::Output ym{};
        EvalD::forward(plus.data(), x, yp);
        EvalD::forward(minus.data(), x, ym);
        for (std::size_t o = 0; o < 2; ++o) {
          const double fd = (yp[o] - ym[o]) / (2.0 * h);
          const double ad = yj[o].v[k - first];
          ASSERT_NEAR(ad, fd, kAbsTol + kRelTol * std::fabs(fd))
              << "case " << c << " parameter " << k << " output " << o;
        }
      }
    }
  }
}

TEST(TskEvaluatorJet, InputGradientMatchesCentralDifferences) {
  SCOPED_TRACE(test::seed_message());
  std::mt19937_64 rng(test::seed() + 2);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (int c = 0; c < 20; ++c) {
    const auto p = random_params(rng);
    const EvalD::Input x{unit(rng), unit(rng), unit(rng), unit(rng)};
    std::array<Jet, EvalD::kParamCount> pj;
    for (std::size_t k = 0; k < p.size(); ++k) pj[k] = Jet(p[k]);
    EvalJ::Input xj;
    for (std::size_t i = 0; i < 4; ++i) xj[i] = Jet(x[i], static_cast<int>(i));
    EvalJ::Output yj;
    EvalJ::forward(pj.data(), xj, yj);
    for (std::size_t i = 0; i < 4; ++i) {
      auto plus = x;
      auto minus = x;
      plus[i] += kStep;
      minus[i] -= kStep;
      EvalD::Output yp{};
      EvalD::Output ym{};
      EvalD::forward(p.data(), plus, yp);
      EvalD::forward(p.data(), minus, ym);
      for (std::size_t o = 0; o < 2; ++o) {
        const double fd = (yp[o] - ym[o]) / (2.0 * kStep);
        ASSERT_NEAR(yj[o].v[static_cast<int>(i)], fd, kAbsTol + kRelTol * std::fabs(fd))
            << "case " << c << " input " << i << " output " << o;
      }
    }
  }
}

TEST(TskEvaluatorJet, FiringAndMembershipsCompileAndAgreeWithDouble) {
  std::mt19937_64 rng(test::seed() + 3);
  const auto p = random_params(rng);
  const EvalD::Input x{0.1, 0.2, 0.3, 0.4};
  EvalD::Firing a{};
  const double total = EvalD::firing(p.data(), x, a);
  std::array<Jet, EvalD::kParamCount> pj;
  for (std::size_t k = 0; k < p.size(); ++k) pj[k] = Jet(p[k]);
  EvalJ::Input xj;
  for (std::size_t i = 0; i < 4; ++i) xj[i] = Jet(x[i]);
  EvalJ::Firing aj;
  const Jet tj = EvalJ::firing(pj.data(), xj, aj);
  EXPECT_NEAR(tj.a, total, kValueTol * total);
  for (std::size_t j = 0; j < a.size(); ++j) EXPECT_NEAR(aj[j].a, a[j], kValueTol);
}

}  // namespace
}  // namespace cmmcomp::fuzzy
