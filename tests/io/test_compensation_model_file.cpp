// SPDX-License-Identifier: MIT
/// @file Loading a model file for the compensator: either architecture, names checked.
#include <gtest/gtest.h>

#include <cmmcomp/error.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <string>
#include <variant>

#include "support/compensation_models.hpp"

namespace cmmcomp::io {
namespace {

PaperModelFileY five_input_file() {
  PaperModelFileY f;
  f.model = test::linear_model_y({1, 2, 3, 4}, {0, 0, 0, 1});
  set_paper_names(f);
  f.training.method = "test";
  f.training.tool_version = "test";
  f.training.cv_rmse = {0, 0, 0, 0};
  f.training.trained_at = "2026-11-23T00:00:00Z";
  return f;
}

std::string error_of(const std::string& text) {
  try {
    parse_compensation_model(text, "m.json");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

TEST(CompensationModelFile, ParsesEitherArchitecture) {
  const auto four = parse_compensation_model(format_model_json(default_model_file()), "d.json");
  EXPECT_EQ(model_inputs(four), 4);
  EXPECT_EQ(model_id(four), default_model_file().model_id);
  const auto five = parse_compensation_model(format_model_json(five_input_file()), "y.json");
  EXPECT_EQ(model_inputs(five), 5);
  EXPECT_EQ(numeric_model_id(five), std::stoull(model_id(five), nullptr, 16));

  compensation::MoveCompensator comp;
  EXPECT_EQ(publish(comp, 2, five), Status::kOk);
  EXPECT_EQ(comp.model_inputs(2), 5);
  EXPECT_EQ(comp.model_id(2), numeric_model_id(five));
}

TEST(CompensationModelFile, RefusesNamesTheCompensatorDoesNotFeed) {
  PaperModelFileY f = five_input_file();
  f.input_names[4] = "z_mm";
  EXPECT_NE(error_of(format_model_json(f))
                .find("m.json: input 4 is 'z_mm'; the compensator "
                      "feeds 'y_mm' there"),
            std::string::npos)
      << error_of(format_model_json(f));
  f = five_input_file();
  f.output_units[3] = "mm";
  EXPECT_NE(error_of(format_model_json(f)).find("unit of output 3 is 'mm'"), std::string::npos);
}

TEST(CompensationModelFile, RefusesOtherArchitecturesSayingWhichItServes) {
  ModelFile<4, 3, 1> single;
  single.model.ranges = default_model_file().model.ranges;
  for (int i = 0; i < 4; ++i) {
    for (int s = 0; s < 3; ++s) single.model.params.width(i, s) = 0.5;
  }
  single.input_names = {"pv_mm_s", "pd_mm", "av_mm_s", "ad_mm"};
  single.input_units = {"mm/s", "mm", "mm/s", "mm"};
  single.output_names = {"rae_um"};
  single.output_units = {"um"};
  single.training.method = "test";
  single.training.tool_version = "test";
  single.training.cv_rmse = {0};
  single.training.trained_at = "2026-11-23T00:00:00Z";
  const std::string e = error_of(format_model_json(single));
  EXPECT_NE(e.find("architecture 4 inputs x 3 sets x 1 outputs"), std::string::npos) << e;
  EXPECT_NE(e.find("serves 4 x 3 x 4"), std::string::npos) << e;
  EXPECT_NE(error_of("{not json").find("m.json"), std::string::npos);
}

}  // namespace
}  // namespace cmmcomp::io
