// SPDX-License-Identifier: MIT
/// @file The schema (include/cmmcomp/schema.hpp): its tables, input sets gathering from a move and
/// a dataset row, and that a model keyed on a new input set (with Z) is served with no change
/// outside the set's one-line definition.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cmmcomp/schema.hpp>
#include <cstring>
#include <memory>
#include <string>

namespace cmmcomp {
namespace {

using compensation::Correction;
using compensation::MoveRequest;

MoveRequest move() {
  MoveRequest m;
  m.pv_mm_s = 40;
  m.pa_mm_s2 = 200;
  m.pd_mm = 30;
  m.av_mm_s = 5;
  m.aa_mm_s2 = 60;
  m.ad_mm = 3;
  m.y_mm = 250;
  m.z_mm = -120;
  return m;
}

TEST(Schema, FeatureTableNamesEachFeatureOnceWithItsRequestField) {
  const MoveRequest m = move();
  EXPECT_STREQ(spec(Feature::kPv).label, "PV");
  EXPECT_STREQ(spec(Feature::kAd).column, "ad_mm");
  EXPECT_STREQ(spec(Feature::kAv).unit, "mm/s");
  EXPECT_EQ(m.*(spec(Feature::kZ).request), -120.0);
  EXPECT_EQ(spec(Feature::kZ).row, nullptr);  // datasets do not carry Z (yet)
  for (std::size_t a = 0; a < kFeatures.size(); ++a) {
    for (std::size_t b = a + 1; b < kFeatures.size(); ++b) {
      EXPECT_STRNE(kFeatures[a].column, kFeatures[b].column);
      EXPECT_STRNE(kFeatures[a].label, kFeatures[b].label);
    }
  }
  EXPECT_STREQ(spec(ErrorParameter::kRae).column, "rae_um");
  EXPECT_STREQ(spec(ErrorParameter::kMpe).key, "mpe");
}

TEST(Schema, InputSetsGatherInTheirOwnOrder) {
  const MoveRequest m = move();
  EXPECT_EQ(PaperInputs::gather(m), (std::array<double, 4>{40, 30, 5, 3}));
  EXPECT_EQ(CarriageInputs::gather(m), (std::array<double, 5>{40, 30, 5, 3, 250}));
  using Odd = InputSet<Feature::kZ, Feature::kPv>;
  EXPECT_EQ(Odd::gather(m), (std::array<double, 2>{-120, 40}));
  EXPECT_STREQ(Odd::columns()[0], "z_mm");
  DatasetRow r;
  r.pv_mm_s = 1;
  r.pd_mm = 2;
  r.av_mm_s = 3;
  r.ad_mm = 4;
  r.y_mm = 5;
  r.mpe_um = 6;
  r.rae_um = -9;
  EXPECT_EQ(CarriageInputs::gather(r), (std::array<double, 5>{1, 2, 3, 4, 5}));
  EXPECT_EQ(gather_errors(r), (std::array<double, 4>{6, 0, 0, -9}));
}

TEST(Schema, DatasetColumnsAreTheFeaturesPaAaAndTheErrors) {
  std::string header;
  for (const DatasetColumn& c : kDatasetColumns)
    header += std::string(header.empty() ? "" : ",") + c.name;
  EXPECT_EQ(header,
            "pv_mm_s,pd_mm,av_mm_s,ad_mm,pa_mm_s2,aa_mm_s2,y_mm,mpe_um,rpe_um,mae_um,rae_um");
}

// The sixth input: Z. Defining the set is the one line below; the compensator template, the
// model type and the gathering need nothing else.
using InputsWithZ =
    InputSet<Feature::kPv, Feature::kPd, Feature::kAv, Feature::kAd, Feature::kY, Feature::kZ>;

/// A model of `Inputs` whose every rule gives y_o = c_o + k_o·x̂_last (x̂ normalised on the last
/// input's range): since the normalised firing strengths sum to 1, the output is exactly that.
template <typename Inputs>
std::unique_ptr<compensation::Model<Inputs>> last_input_model(double lo, double hi) {
  auto m = std::make_unique<compensation::Model<Inputs>>();
  for (int i = 0; i < Inputs::kCount; ++i) {
    m->ranges[static_cast<std::size_t>(i)] = {-1000.0, 1000.0};
    for (int s = 0; s < 3; ++s) {
      m->params.centre(i, s) = 0.5 * s;
      m->params.width(i, s) = 0.4;
    }
  }
  m->ranges[static_cast<std::size_t>(Inputs::kCount - 1)] = {lo, hi};
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < compensation::Model<Inputs>::kRules; ++j) {
      m->params.consequent(o, j, 0) = 1.0 + o;
      m->params.consequent(o, j, Inputs::kCount) = 2.0;
    }
  }
  return m;
}

TEST(Schema, AModelWithZAsSixthInputIsServedByTheSameCompensator) {
  static_assert(InputsWithZ::kCount == 6);
  compensation::BasicMoveCompensator<PaperInputs, InputsWithZ> comp;
  const auto model = last_input_model<InputsWithZ>(-500.0, 0.0);
  ASSERT_EQ(comp.publish(1, *model, 77), Status::kOk);
  EXPECT_EQ(comp.model_inputs(1), 6);
  MoveRequest m = move();
  m.axis = 1;
  Correction out;
  for (double z : {-400.0, -250.0, -10.0}) {
    m.z_mm = z;
    ASSERT_EQ(comp.before_approach(m, out), Status::kOk);
    const double x = (z + 500.0) / 500.0;  // z normalised on [-500, 0]
    EXPECT_NEAR(out.rae_um, 4.0 + 2.0 * x, 1e-9) << z;
    EXPECT_NEAR(out.mpe_um, 1.0 + 2.0 * x, 1e-9) << z;
    EXPECT_EQ(out.model_id, 77u);
  }
  // The same axis then serves a model of the other set: the publish replaces it.
  ASSERT_EQ(comp.publish(1, *last_input_model<PaperInputs>(1.0, 5.0), 78), Status::kOk);
  EXPECT_EQ(comp.model_inputs(1), 4);
  ASSERT_EQ(comp.before_approach(m, out), Status::kOk);
  EXPECT_NEAR(out.rae_um, 4.0 + 2.0 * (3.0 - 1.0) / 4.0, 1e-9);  // AD = 3 on [1, 5]
}

TEST(Schema, TheStaticCompensatorServesTheNewSetToo) {
  static compensation::StaticMoveCompensator<compensation::Model<InputsWithZ>, 1> firmware;
  const auto model = last_input_model<InputsWithZ>(-500.0, 0.0);
  ASSERT_EQ(firmware.publish(0, *model, 5), Status::kOk);
  MoveRequest m = move();
  m.z_mm = -250.0;
  Correction out;
  ASSERT_EQ(firmware.before_approach(m, out), Status::kOk);
  EXPECT_NEAR(out.rae_um, 5.0, 1e-9);
}

}  // namespace
}  // namespace cmmcomp
