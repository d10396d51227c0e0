// SPDX-License-Identifier: MIT
/// @file Run by the ctest default_model_reproducible after scripts/train-default-model.sh has
/// retrained the default model into the file named by argv[1]: same training data, same
/// predictions as the committed data/models/default.json (compiled in).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <string>

namespace {

std::string g_retrained;  // argv[1]

// Retrained by the script (ctest fixture default_model_retrained): same predictions. Tolerance
// 1e-6 um: the twin, the design and the training are deterministic; what may differ across
// machines is the last bits of BLAS inside Ceres, which LM damps.
TEST(DefaultModel, ScriptReproducesIt) {
  using namespace cmmcomp;
  ASSERT_FALSE(g_retrained.empty()) << "usage: check_default_model_reproducible RETRAINED.json";
  const auto committed = io::default_model_file();
  const auto again = io::load_model_file<4, 3, 4>(g_retrained);
  EXPECT_EQ(committed.training.data_file_sha256, again.training.data_file_sha256)
      << "the script's training data changed";
  double worst = 0;
  for (int k = 0; k < 625; ++k) {  // a 5^4 grid over the ranges
    std::array<double, 4> x{};
    int code = k;
    for (std::size_t i = 0; i < 4; ++i, code /= 5) {
      const auto& r = committed.model.ranges[i];
      x[i] = r.lo + (r.hi - r.lo) * (code % 5) / 4.0;
    }
    std::array<double, 4> a{}, b{};
    ASSERT_TRUE(ok(fuzzy::evaluate(committed.model, x, a, fuzzy::DomainPolicy::kClamp)));
    ASSERT_TRUE(ok(fuzzy::evaluate(again.model, x, b, fuzzy::DomainPolicy::kClamp)));
    for (std::size_t o = 0; o < 4; ++o) worst = std::max(worst, std::abs(a[o] - b[o]));
  }
  EXPECT_LT(worst, 1e-6) << "largest prediction difference " << worst << " um";
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  if (argc > 1) g_retrained = argv[1];
  return RUN_ALL_TESTS();
}
