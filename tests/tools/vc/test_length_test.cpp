// SPDX-License-Identifier: MIT
/// @file The length test's geometry and evaluation with analytic fakes: bidirectional errors add,
/// the correction is applied with the right sign, MPE_E, time per point.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/length_geometry.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/probe_setting.hpp>
#include <cmmcomp/vc/qualification.hpp>
#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

#include "report.hpp"

namespace cmmcomp::vc {
namespace {

/// The machine of the tests: the same RAE at every touch.
class ConstantRae final : public TouchErrorModel {
 public:
  explicit ConstantRae(double rae_um) : rae_um_(rae_um) {}
  double rae_um(const ProbeSetting&, double, std::uint64_t) override { return rae_um_; }

 private:
  double rae_um_;
};

/// An agent that predicts RAE = `predicted_um` and answers +RAE·d, as the protocol says.
class FakeAgent final : public CorrectionSource {
 public:
  FakeAgent(std::string label, double predicted_um)
      : label_(std::move(label)), where_("fake"), predicted_um_(predicted_um) {}
  Answer ask(const compensation::MoveRequest& m) override {
    ++calls;
    last = m;
    Answer a;
    a.usable = true;
    a.flags = compensation::kFlagOk;
    a.rae_um = predicted_um_;
    for (int i = 0; i < 3; ++i) {
      a.correction_um[static_cast<std::size_t>(i)] =
          predicted_um_ * m.direction[static_cast<std::size_t>(i)];
    }
    a.model_id = 42;
    return a;
  }
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }
  int calls = 0;
  compensation::MoveRequest last;

 private:
  std::string label_;
  std::string where_;
  double predicted_um_;
};

LengthProgram small_program() {
  LengthProgram p;
  p.lengths_mm = {20, 400};
  p.y_mm = {0, 500};
  p.repeats = 2;
  return p;
}

TEST(LengthGeometry, ScalePointLagsTheTipAlongTheMotion) {
  // Tip ahead by 2 µm moving +X: the scale reads 2 µm short of the face.
  EXPECT_NEAR(scale_point_mm(100.0, +1, 2.0), 99.998, 1e-12);
  // The compensator.md hand example: −X, scale 100.000, tip 99.998 → RAE +2, correction −2 µm.
  EXPECT_NEAR(scale_point_mm(99.998, -1, 2.0), 100.000, 1e-12);
  EXPECT_NEAR(corrected_point_mm(100.000, -2.0), 99.998, 1e-12);
}

TEST(LengthGeometry, FacesAreOpposedAndApproachedFromOppositeSides) {
  EXPECT_EQ(direction_of(Face::kA), +1);
  EXPECT_EQ(direction_of(Face::kB), -1);
  EXPECT_DOUBLE_EQ(face_position_mm(Face::kA, 100, 50), 150);
  EXPECT_DOUBLE_EQ(face_position_mm(Face::kB, 100, 50), 100);
}

TEST(LengthGeometry, ConstantRaeGivesMinusTwoRaeUncompensated) {
  for (double rae : {-8.6, -1.0, 0.0, 3.0}) {
    const double a = scale_point_mm(face_position_mm(Face::kA, 100, 200), +1, rae);
    const double b = scale_point_mm(face_position_mm(Face::kB, 100, 200), -1, rae);
    EXPECT_NEAR(length_error_um(a, b, 200), -2.0 * rae, 1e-9) << rae;
    EXPECT_NEAR(
        length_error_um(corrected_point_mm(a, +rae), corrected_point_mm(b, -rae), 200), 0.0, 1e-9);
  }
}

TEST(LengthGeometry, MpeEIsOnePointNinePlusLOver300) {
  EXPECT_DOUBLE_EQ(mpe_e_um(0), 1.9);
  EXPECT_DOUBLE_EQ(mpe_e_um(300), 2.9);
  EXPECT_NEAR(mpe_e_um(20), 1.9666666666666666, 1e-12);
  EXPECT_NEAR(mpe_e_um(400), 3.2333333333333334, 1e-12);
}

TEST(LengthTest, ExactPredictionCancelsAndWrongSignDoubles) {
  const double rae = -5.0;
  ConstantRae machine(rae);
  FakeAgent exact("exact", rae);
  FakeAgent none("zero", 0.0);
  FakeAgent flipped("flipped", -rae);
  const LengthProgram program = small_program();
  const LengthTestResult r = run_length_test(program, machine, {&exact, &none, &flipped});
  ASSERT_EQ(r.cases.size(), 4u);
  for (const CaseResult& c : r.cases) {
    EXPECT_NEAR(c.fast_uncompensated_um, -2 * rae, 1e-6);
    EXPECT_NEAR(c.slow_um, -2 * rae, 1e-6);
    EXPECT_NEAR(c.fast_compensated_um[0], 0.0, 1e-6);
    EXPECT_NEAR(c.fast_compensated_um[1], -2 * rae, 1e-6);
    EXPECT_NEAR(c.fast_compensated_um[2], -4 * rae, 1e-6);
    EXPECT_DOUBLE_EQ(c.mpe_e_um, mpe_e_um(c.length_mm));
  }
  for (const YSummary& y : r.per_y) {
    EXPECT_FALSE(y.fast_uncompensated_pass);
    EXPECT_TRUE(y.fast_compensated_pass[0]);
    EXPECT_FALSE(y.fast_compensated_pass[2]);
    EXPECT_NEAR(y.fast_compensated_max_um[0], 0.0, 1e-6);
  }
  EXPECT_EQ(r.unusable_answers, 0u);
}

TEST(LengthTest, AsksOnlyForFastPointsWithTheirMove) {
  ConstantRae machine(1.0);
  FakeAgent agent("a", 1.0);
  const LengthProgram program = small_program();
  const LengthTestResult r = run_length_test(program, machine, {&agent});
  // 2 lengths × 2 Y × 2 repeats × 2 faces, fast only; every point is logged (slow and fast).
  EXPECT_EQ(agent.calls, 16);
  EXPECT_EQ(r.points.size(), 32u);
  EXPECT_DOUBLE_EQ(agent.last.pv_mm_s, program.fast.pv_mm_s);
  EXPECT_DOUBLE_EQ(agent.last.ad_mm, program.fast.ad_mm);
  EXPECT_DOUBLE_EQ(agent.last.y_mm, 500);
  EXPECT_DOUBLE_EQ(agent.last.direction[0], +1.0);  // the last point is a face A
  for (std::size_t i = 0; i < r.points.size(); ++i) EXPECT_EQ(r.points[i].index, i);
}

TEST(LengthTest, UnusableAnswerLeavesTheScalePoint) {
  class Refusing final : public CorrectionSource {
   public:
    Answer ask(const compensation::MoveRequest&) override {
      Answer a;
      a.note = "refused";
      return a;
    }
    const std::string& label() const noexcept override { return s_; }
    const std::string& where() const noexcept override { return s_; }

   private:
    std::string s_ = "r";
  } refusing;
  ConstantRae machine(2.0);
  const LengthTestResult r = run_length_test(small_program(), machine, {&refusing});
  EXPECT_EQ(r.unusable_answers, 16u);
  for (const CaseResult& c : r.cases) EXPECT_NEAR(c.fast_compensated_um[0], -4.0, 1e-6);
}

/// A machine whose touch lags by a static part that grows with Y plus a part of the setting
/// (proportional to AV) that grows with Y too, as the twin's hose drag and mode participation do;
/// it logs the noise index of every touch.
class StaticPlusDynamic final : public TouchErrorModel {
 public:
  static double static_um(double y) { return -3.6 - 0.0066 * y; }
  static double dynamic_um(const ProbeSetting& s, double y) {
    return -0.1 * s.av_mm_s * (1 + y / 500);
  }
  double rae_um(const ProbeSetting& s, double y, std::uint64_t index) override {
    indices.push_back(index);
    return static_um(y) + dynamic_um(s, y);
  }
  std::vector<std::uint64_t> indices;
};

TEST(Qualification, RemovesTheStaticLagAndTheSettingsLagAtTheSphere) {
  StaticPlusDynamic machine;
  FakeAgent agent("a", -1.0);
  LengthProgram program = small_program();
  const LengthTestResult raw = run_length_test(program, machine, {&agent});
  EXPECT_FALSE(raw.qualification.has_value());
  program.qualify = true;
  program.qualification.sphere_y_mm = 250;
  program.qualification.touches = 3;
  const LengthTestResult q = run_length_test(program, machine, {&agent});
  ASSERT_TRUE(q.qualification.has_value());
  ASSERT_EQ(q.cases.size(), raw.cases.size());
  const ProbeSetting& fast = program.fast;
  const ProbeSetting& map = program.qualification.map_setting;  // the slow reference's numbers
  for (std::size_t i = 0; i < q.cases.size(); ++i) {
    const CaseResult& c = q.cases[i];
    const double y = c.y_mm;
    // Uncompensated raw: E = −2·RAE; qualified: only how the setting's lag beyond the map's
    // changes from the sphere's Y to this Y remains.
    EXPECT_NEAR(raw.cases[i].fast_uncompensated_um,
                -2 * (StaticPlusDynamic::static_um(y) + StaticPlusDynamic::dynamic_um(fast, y)),
                1e-6);
    const double residual =
        (StaticPlusDynamic::dynamic_um(fast, y) - StaticPlusDynamic::dynamic_um(map, y)) -
        (StaticPlusDynamic::dynamic_um(fast, 250) - StaticPlusDynamic::dynamic_um(map, 250));
    EXPECT_NEAR(c.fast_uncompensated_um, -2 * residual, 1e-6) << "Y " << y;
    EXPECT_GT(std::fabs(c.fast_uncompensated_um), 0.1);  // not everything is removed
    // The slow reference is the map's setting: nothing remains of it.
    EXPECT_NEAR(c.slow_um, 0.0, 1e-6);
    // The compensated column is not qualified.
    EXPECT_DOUBLE_EQ(c.fast_compensated_um[0], raw.cases[i].fast_compensated_um[0]);
  }
  // The map holds the nodes 0, 250 (the sphere) and 500.
  EXPECT_EQ(q.qualification->reference.map_y_mm, (std::vector<double>{0, 250, 500}));
  EXPECT_NEAR(q.qualification->reference.map_um[1],
              StaticPlusDynamic::static_um(250) + StaticPlusDynamic::dynamic_um(map, 250),
              1e-12);
}

TEST(Qualification, TakesItsOwnNoiseStreamsBeforeTheProgram) {
  StaticPlusDynamic machine;
  FakeAgent agent("a", 0.0);
  LengthProgram program = small_program();
  program.qualify = true;
  program.qualification.touches = 4;
  const LengthTestResult r = run_length_test(program, machine, {&agent});
  // 3 map nodes (0, 250, 500) and 2 settings, 4 touches each.
  const std::size_t touches = (3 + 2) * 4;
  EXPECT_EQ(r.qualification->touches_used, touches);
  ASSERT_EQ(machine.indices.size(), touches + r.points.size());
  for (std::size_t i = 0; i < touches; ++i) {
    EXPECT_EQ(machine.indices[i], kQualificationIndex0 + i);
  }
  // The program's points keep their streams 0, 1, 2, …: the qualification changes none of them.
  for (std::size_t i = 0; i < r.points.size(); ++i) {
    EXPECT_EQ(machine.indices[touches + i], i);
    EXPECT_EQ(r.points[i].index, i);
  }
}

TEST(Qualification, ThePointLogCarriesTheQualifiedPoint) {
  StaticPlusDynamic machine;
  FakeAgent agent("a", 0.0);
  LengthProgram program = small_program();
  program.qualify = true;
  const LengthTestResult r = run_length_test(program, machine, {&agent});
  const std::string path = ::testing::TempDir() + "/qualified_points.csv";
  write_points_csv(path, r);
  std::ifstream in(path);
  std::string header;
  std::getline(in, header);
  ASSERT_EQ(header.substr(header.rfind(',') + 1), "qualified_mm");
  std::string row;
  std::size_t rows = 0;
  while (std::getline(in, row)) {
    // The row's last field is the qualified point; the point record says what it must be.
    const double logged = std::stod(row.substr(row.rfind(',') + 1));
    const std::uint64_t index = std::stoull(row.substr(0, row.find(',')));
    const PointRecord& p = r.points[index];
    EXPECT_NEAR(logged, p.qualified_mm, 1e-7);
    EXPECT_NEAR(
        p.qualified_mm,
        p.scale_mm + r.qualification->removed_um(p.setting, p.y_mm) * direction_of(p.face) * 1e-3,
        1e-12);
    EXPECT_GT(std::fabs(p.qualified_mm - p.scale_mm), 1e-3);  // the static lag is µm
    ++rows;
  }
  EXPECT_EQ(rows, r.points.size());  // one agent: one row a point
}

TEST(Qualification, RemovesTheMapAndTheSettingsOffset) {
  Qualification q;
  q.reference.map_y_mm = {0, 250, 500};
  q.reference.map_um = {-4, -5, -8};
  q.settings = {default_fast_setting()};
  q.offsets_um = {-1.5};
  EXPECT_DOUBLE_EQ(q.removed_um(default_fast_setting(), 250), -6.5);
  EXPECT_DOUBLE_EQ(q.removed_um(default_fast_setting(), 400), -5 + 0.6 * -3 - 1.5);
  EXPECT_THROW((void)q.offset_um(default_slow_setting()), Error);
}

TEST(Qualification, ABadPlanIsAConfigErrorOnlyWhenAskedFor) {
  LengthProgram p = small_program();
  p.qualification.touches = 0;
  EXPECT_NO_THROW(p.validate());
  p.qualify = true;
  EXPECT_THROW(p.validate(), ConfigError);
  p.qualification.touches = 1;
  p.qualification.sphere_y_mm = -1;
  EXPECT_THROW(p.validate(), ConfigError);
  p.qualification.sphere_y_mm = std::nan("");
  EXPECT_THROW(p.validate(), ConfigError);
  p.qualification.sphere_y_mm = 250;
  EXPECT_NO_THROW(p.validate());
}

TEST(ProbeSetting, TimePerPointIsPositioningPlusApproach) {
  // Trapezoids: PD/PV + PV/PA, then the approach AD/AV + AV/(2·AA) (it ends moving at AV).
  const ProbeSetting fast = default_fast_setting();
  EXPECT_NEAR(time_per_point_s(fast), 60.0 / 100 + 100.0 / 200 + 10.0 / 16 + 16.0 / 120, 1e-9);
  const ProbeSetting slow = default_slow_setting();
  EXPECT_NEAR(time_per_point_s(slow), 60.0 / 20 + 20.0 / 200 + 2.0 / 1 + 1.0 / 120, 1e-9);
  // The controller's dwell adds itself. Smoothing over T lengthens every ramp by T and shortens
  // the cruises by the distance that takes: positioning lasts T longer, the approach T/2.
  EXPECT_NEAR(time_per_point_s(fast, 0.5, 0.04), time_per_point_s(fast) + 0.5 + 1.5 * 0.04, 1e-9);
}

TEST(ProbeSetting, ParsesOverridesAndRejectsNonsense) {
  const ProbeSetting s = parse_setting("pv=80,av=12", default_fast_setting());
  EXPECT_DOUBLE_EQ(s.pv_mm_s, 80);
  EXPECT_DOUBLE_EQ(s.av_mm_s, 12);
  EXPECT_DOUBLE_EQ(s.pd_mm, 60);
  EXPECT_THROW(parse_setting("pv=-1", s), ConfigError);
  EXPECT_THROW(parse_setting("speed=3", s), ConfigError);
  EXPECT_THROW(parse_setting("pv", s), ConfigError);
  EXPECT_THROW(parse_setting("pv=3x", s), ConfigError);
}

TEST(LengthProgram, RejectsEmptyAndNonPositive) {
  LengthProgram p;
  p.lengths_mm = {};
  EXPECT_THROW(p.validate(), ConfigError);
  p = LengthProgram{};
  p.lengths_mm = {0};
  EXPECT_THROW(p.validate(), ConfigError);
  p = LengthProgram{};
  p.repeats = 0;
  EXPECT_THROW(p.validate(), ConfigError);
}

}  // namespace
}  // namespace cmmcomp::vc
