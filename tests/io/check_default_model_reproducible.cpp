// SPDX-License-Identifier: MIT
/// @file Run by the ctest default_model_reproducible after scripts/train-default-model.sh has
/// retrained the shipped models: `check_default_model_reproducible COMMITTED RETRAINED
/// [--compare-interval]` (either architecture): same training data, same predictions, and with
/// --compare-interval the same prediction interval.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cstdio>
#include <string>
#include <tuple>
#include <variant>

namespace {

std::string g_committed, g_retrained;  // argv[1], argv[2]
bool g_compare_interval = false;       // argv[3] == "--compare-interval"

/// Largest |difference| of the outputs of two models of the same architecture over a 5^n grid
/// of the first one's ranges [µm].
template <typename File>
double largest_difference(const File& a, const File& b) {
  constexpr std::size_t n = std::tuple_size_v<decltype(a.model.ranges)>;
  int points = 1;
  for (std::size_t i = 0; i < n; ++i) points *= 5;
  double worst = 0;
  for (int k = 0; k < points; ++k) {
    std::array<double, n> x{};
    int code = k;
    for (std::size_t i = 0; i < n; ++i, code /= 5) {
      const auto& r = a.model.ranges[i];
      x[i] = r.lo + (r.hi - r.lo) * (code % 5) / 4.0;
    }
    std::array<double, 4> ya{}, yb{};
    EXPECT_TRUE(cmmcomp::ok(
        cmmcomp::fuzzy::evaluate(a.model, x, ya, cmmcomp::fuzzy::DomainPolicy::kClamp)));
    EXPECT_TRUE(cmmcomp::ok(
        cmmcomp::fuzzy::evaluate(b.model, x, yb, cmmcomp::fuzzy::DomainPolicy::kClamp)));
    for (std::size_t o = 0; o < 4; ++o) worst = std::max(worst, std::abs(ya[o] - yb[o]));
  }
  return worst;
}

// The interval (docs/uncertainty.md). Its nominal coverage and sample count must be equal in
// every build. Without --compare-interval (the sanitizer builds, whose retrain calibrates on the
// ridge folds only to save minutes) that is all. With it (the release build, whose retrain uses
// the script's own fold models) each output's half-width must match too, at the box's centre
// (κ = 0) and at the mean corner share of uniformly drawn moves, κ̄ = 1/9 + 4/(45·n): within
// 10 % + 0.1 µm. Why not tighter: round-off moves the fold models' residuals as it moves the
// predictions (0.08 µm between CPUs, above), and the per-output choice of the narrower interval
// may flip between two nearly equal ones (MPE's differ by 0.3 % in the shipped model), which
// keeps h·(1 + k·κ̄) but may exchange h and k. Measured 2026-12-06: the ASan build, retraining
// with the script's fold models (829 s; its predictions differ by up to 0.31 µm, below), flips
// MPE's choice from the ridge folds to the folds as served, and its U95 lies within 0.03 µm of the
// shipped one at both κ (MPE h 2.640 against 2.663 µm). What it catches: another fold-model kind
// (RPE 2.06 µm with the ridge folds against 1.55 µm as shipped), another coverage, other data. The
// extrapolation gain is not compared: it is noise-driven (docs/uncertainty.md, "Known limits").
template <typename File>
void expect_same_interval(const File& committed, const File& again) {
  ASSERT_EQ(committed.interval.available(), again.interval.available());
  if (!committed.interval.available()) return;
  EXPECT_EQ(committed.interval.coverage, again.interval.coverage);
  EXPECT_EQ(committed.interval_samples, again.interval_samples);
  if (!g_compare_interval) return;
  constexpr double n = static_cast<double>(std::tuple_size_v<decltype(committed.model.ranges)>);
  for (const double kappa : {0.0, 1.0 / 9.0 + 4.0 / (45.0 * n)}) {
    std::array<double, 4> uc{}, ua{};
    cmmcomp::fuzzy::interval_half_widths(committed.interval, 0.0, kappa, uc);
    cmmcomp::fuzzy::interval_half_widths(again.interval, 0.0, kappa, ua);
    for (std::size_t o = 0; o < uc.size(); ++o) {
      EXPECT_LE(std::abs(uc[o] - ua[o]), 0.1 * uc[o] + 0.1)
          << committed.output_names[o] << " U95 at corner share " << kappa << ": committed "
          << uc[o] << " um, retrained " << ua[o] << " um (method '" << committed.interval_method
          << "' against '" << again.interval_method << "')";
    }
  }
}

// Tolerance 0.4 µm. The twin, the designs and the training data are deterministic and the same
// bits in every build: the data file's SHA-256 must match exactly (below). What differs between
// builds is the training's round-off (Eigen's SIMD kernels follow -march, in cmmcomp's code and
// inside Ceres' headers), which Levenberg–Marquardt amplifies rather than damps; the same build
// retrains the same model bit for bit. Measured: on 2026-12-02 the portable ASan build retrained
// to within 0.029 µm of the x86-64-v3 model, and the same release build on an AMD EPYC machine to
// within 0.078 µm; on 2026-12-04, after the models were retrained on the exponential integrator's
// data, the ASan build retrains the 4-input model 0.31 µm away (0.16 µm with Eigen's explicit
// SIMD off everywhere, so that is not the whole cause; not isolated further). Any real change of
// data or method moves the predictions by micrometres, and the data hash is compared exactly.
TEST(DefaultModel, ScriptReproducesIt) {
  using namespace cmmcomp;
  ASSERT_FALSE(g_retrained.empty())
      << "usage: check_default_model_reproducible COMMITTED.json RETRAINED.json";
  const auto committed = io::load_compensation_model(g_committed);
  const auto again = io::load_compensation_model(g_retrained);
  ASSERT_EQ(committed.index(), again.index()) << "the architecture changed";
  std::visit(
      [&](const auto& c) {
        using File = std::decay_t<decltype(c)>;
        const File& a = std::get<File>(again);
        EXPECT_EQ(c.training.data_file_sha256, a.training.data_file_sha256)
            << "the script's training data changed";
        const double worst = largest_difference(c, a);
        EXPECT_LT(worst, 0.4) << "largest prediction difference " << worst << " um";
        expect_same_interval(c, a);
      },
      committed);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  if (argc > 2) {
    g_committed = argv[1];
    g_retrained = argv[2];
  }
  if (argc > 3) {
    if (std::string(argv[3]) != "--compare-interval") {
      std::fprintf(stderr, "unknown option '%s' (only --compare-interval)\n", argv[3]);
      return 2;
    }
    g_compare_interval = true;
  }
  return RUN_ALL_TESTS();
}
