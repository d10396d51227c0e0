// SPDX-License-Identifier: MIT
/// @file The shipped default model: the compiled-in copy is data/models/default.json, it is
/// valid and covers the design's ranges. Its reproducibility: check_default_model_reproducible.cpp.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <string>

namespace cmmcomp::io {
namespace {

#ifndef CMMCOMP_SOURCE_DIR
#error "CMMCOMP_SOURCE_DIR must name the source tree"
#endif

TEST(DefaultModel, CompiledInCopyIsTheDataFile) {
  const auto embedded = default_model_file();
  const auto file =
      load_model_file<4, 3, 4>(std::string(CMMCOMP_SOURCE_DIR) + "/data/models/default.json");
  EXPECT_EQ(embedded.checksum, file.checksum);
  EXPECT_EQ(embedded.model_id.size(), 16u);
  EXPECT_TRUE(fuzzy::validate(embedded.model));
}

TEST(DefaultModel, CoversThePaperDesignRanges) {
  // The L18 corners are in the training data, so the ranges are exactly the design's.
  const auto m = default_model_file();
  const std::array<std::array<double, 2>, 4> design{{{40, 100}, {40, 80}, {8, 16}, {5, 15}}};
  for (std::size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(m.model.ranges[i].lo, design[i][0]) << m.input_names[i];
    EXPECT_EQ(m.model.ranges[i].hi, design[i][1]) << m.input_names[i];
  }
  EXPECT_EQ(m.input_names[0], "pv_mm_s");
  EXPECT_EQ(m.output_names[3], "rae_um");
}

}  // namespace
}  // namespace cmmcomp::io
