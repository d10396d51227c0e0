// SPDX-License-Identifier: MIT
/// @file Loading a model file for the compensator: any served input set, names checked.
#include <gtest/gtest.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <string>
#include <variant>

#include "support/compensation_models.hpp"

namespace cmmcomp::io {
namespace {

ModelFileOf<CarriageInputs> five_input_file() {
  ModelFileOf<CarriageInputs> f;
  f.model = test::linear_model_y({1, 2, 3, 4}, {0, 0, 0, 1});
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

TEST(CompensationModelFile, NamesAndUnitsComeFromTheSchema) {
  const ModelFileOf<CarriageInputs> f;
  ASSERT_EQ(f.input_names.size(), 5u);
  EXPECT_EQ(f.input_names[0], "pv_mm_s");
  EXPECT_EQ(f.input_names[4], "y_mm");
  EXPECT_EQ(f.input_units[2], "mm/s");
  EXPECT_EQ(f.output_names[3], "rae_um");
  EXPECT_EQ(f.output_units[0], "um");
  EXPECT_EQ(schema_name_problem<CarriageInputs>(f), "");
  EXPECT_EQ(schema_name_problem<PaperInputs>(ModelFileOf<PaperInputs>()), "");
}

TEST(CompensationModelFile, ParsesEveryServedInputSet) {
  const auto four = parse_compensation_model(format_model_json(default_model_file()), "d.json");
  EXPECT_TRUE(std::holds_alternative<ModelFileOf<PaperInputs>>(four));
  EXPECT_EQ(model_inputs(four), 4);
  EXPECT_EQ(model_id(four), default_model_file().model_id);
  const auto five = parse_compensation_model(format_model_json(five_input_file()), "y.json");
  EXPECT_TRUE(std::holds_alternative<ModelFileOf<CarriageInputs>>(five));
  EXPECT_EQ(model_inputs(five), 5);
  EXPECT_EQ(numeric_model_id(five), std::stoull(model_id(five), nullptr, 16));

  compensation::MoveCompensator comp;
  EXPECT_EQ(publish(comp, 2, five), Status::kOk);
  EXPECT_EQ(comp.model_inputs(2), 5);
  EXPECT_EQ(comp.model_id(2), numeric_model_id(five));
}

/// A move of the shipped model's training box (AV 12, AD 10 mm, PA 200, AA 60 mm/s², Y 250).
compensation::MoveRequest move_in_the_box(double pv_mm_s, double pd_mm) {
  compensation::MoveRequest m;
  m.direction = {1.0, 0.0, 0.0};
  m.pv_mm_s = pv_mm_s;
  m.pa_mm_s2 = 200.0;
  m.pd_mm = pd_mm;
  m.av_mm_s = 12.0;
  m.aa_mm_s2 = 60.0;
  m.ad_mm = 10.0;
  m.y_mm = 250.0;
  return m;
}

// The shipped model carries its interval calibration, and publishing the file carries it into
// every Correction (docs/uncertainty.md).
TEST(CompensationModelFile, TheShippedModelPublishesItsInterval) {
  const auto& f = default_model_file();
  ASSERT_TRUE(f.interval.available()) << "data/models/default.json has no uncertainty";
  EXPECT_EQ(f.interval.coverage, 0.95);
  const auto any = parse_compensation_model(format_model_json(f), "d.json");
  compensation::MoveCompensator comp;
  ASSERT_EQ(publish(comp, 0, any), Status::kOk);
  const compensation::MoveRequest m = move_in_the_box(40.0, 40.0);
  compensation::Correction c;
  ASSERT_EQ(comp.before_approach(m, c), Status::kOk);
  EXPECT_EQ(c.flags & compensation::kFlagNoUncertainty, 0u);
  // PV and PD at the low ends of their ranges, AV and AD mid-range: corner share ((1 + 1)/4)².
  const auto x = compensation::Model<PaperInputs>::input(m);
  ASSERT_EQ(fuzzy::corner_share(f.model.ranges, x), 0.25);
  for (std::size_t o = 0; o < 4; ++o) {
    EXPECT_DOUBLE_EQ(c.u95_um[o],
                     f.interval.half_width[o] * (1.0 + 0.25 * f.interval.corner_gain[o]))
        << o;
  }
  // A file without a calibration publishes as "no uncertainty".
  ModelFileOf<PaperInputs> plain = f;
  plain.interval = {};
  ASSERT_EQ(publish(comp, 0, parse_compensation_model(format_model_json(plain), "p.json")),
            Status::kOk);
  ASSERT_EQ(comp.before_approach(m, c), Status::kOk);
  EXPECT_NE(c.flags & compensation::kFlagNoUncertainty, 0u);
}

// The shipped model records the accelerations it was trained at (PA 200, AA 60 mm/s²) and
// publishes them: a move at PA 1200 (issue 36: answered as plain OK before) is refused, one at
// PA 210 flagged; a format-3 file of the same network checks only its inputs.
TEST(CompensationModelFile, TheShippedModelPublishesItsConditions) {
  const auto& f = default_model_file();
  ASSERT_TRUE(f.conditions.pa_mm_s2 && f.conditions.aa_mm_s2);
  EXPECT_EQ(*f.conditions.pa_mm_s2, (ConditionRange{200.0, 200.0}));
  EXPECT_EQ(*f.conditions.aa_mm_s2, (ConditionRange{60.0, 60.0}));
  ASSERT_TRUE(f.conditions.dwell_s && f.conditions.smoothing_s);
  EXPECT_EQ(f.conditions.axis, "x");
  EXPECT_EQ(f.conditions.noise_floor.size(), 4u);
  const auto any = parse_compensation_model(format_model_json(f), "d.json");
  EXPECT_EQ(training_conditions(any), f.conditions);
  compensation::MoveCompensator comp;
  ASSERT_EQ(publish(comp, 0, any), Status::kOk);
  compensation::MoveRequest m = move_in_the_box(70.0, 60.0);
  compensation::Correction c;
  EXPECT_EQ(comp.before_approach(m, c), Status::kOk);
  m.pa_mm_s2 = 210.0;
  EXPECT_EQ(comp.before_approach(m, c), Status::kOutsideDomain);
  EXPECT_NE(c.flags & compensation::kFlagOutsideDomain, 0u);
  m.pa_mm_s2 = 1200.0;
  EXPECT_EQ(comp.before_approach(m, c), Status::kOutsideDomainRejected);
  ModelFileOf<PaperInputs> old = f;
  old.conditions = {};
  ASSERT_EQ(publish(comp, 0, parse_compensation_model(format_model_json(old), "o.json")),
            Status::kOk);
  EXPECT_EQ(comp.before_approach(m, c), Status::kOk);
}

// Every interface reports U95: a file calibrated at another coverage is not served (issue 36
// §7: the protocols used to label a 50 % half-width U95).
TEST(CompensationModelFile, AnIntervalAtAnotherCoverageIsNotServed) {
  ModelFileOf<PaperInputs> half = default_model_file();
  half.interval.coverage = 0.5;
  compensation::MoveCompensator comp;
  std::string why;
  EXPECT_EQ(publish(comp, 0, parse_compensation_model(format_model_json(half), "h.json"), &why),
            Status::kInvalidInput);
  EXPECT_NE(why.find("calibrated at 50 % coverage, but every interface of the compensator reports "
                     "U95"),
            std::string::npos)
      << why;
  EXPECT_FALSE(comp.has_model(0));
  ModelFileOf<PaperInputs> none = default_model_file();
  none.interval = {};  // no calibration: served, flagged NO_UNCERTAINTY
  EXPECT_EQ(publish(comp, 0, parse_compensation_model(format_model_json(none), "n.json")),
            Status::kOk);
}

TEST(CompensationModelFile, RefusesNamesTheCompensatorDoesNotFeed) {
  ModelFileOf<CarriageInputs> f = five_input_file();
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
  single.input_names = ModelFileOf<PaperInputs>().input_names;
  single.input_units = ModelFileOf<PaperInputs>().input_units;
  single.output_names = {"rae_um"};
  single.output_units = {"um"};
  single.training.method = "test";
  single.training.tool_version = "test";
  single.training.cv_rmse = {0};
  single.training.trained_at = "2026-11-23T00:00:00Z";
  const std::string e = error_of(format_model_json(single));
  EXPECT_NE(e.find("architecture 4 inputs x 3 sets x 1 outputs"), std::string::npos) << e;
  EXPECT_NE(e.find("serves 4 x 3 x 4 (PV, PD, AV, AD) or 5 x 3 x 4 (PV, PD, AV, AD, Y)"),
            std::string::npos)
      << e;
  EXPECT_NE(error_of("{not json").find("m.json"), std::string::npos);
}

}  // namespace
}  // namespace cmmcomp::io
