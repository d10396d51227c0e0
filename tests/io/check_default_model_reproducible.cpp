// SPDX-License-Identifier: MIT
/// @file Run by the ctest default_model_reproducible after scripts/train-default-model.sh has
/// retrained the shipped models: `check_default_model_reproducible COMMITTED RETRAINED`
/// (either architecture): same training data, same predictions.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <string>
#include <variant>

namespace {

std::string g_committed, g_retrained;  // argv[1], argv[2]

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
  return RUN_ALL_TESTS();
}
