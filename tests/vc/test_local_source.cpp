// SPDX-License-Identifier: MIT
/// @file vc::LocalSource (cmmcomp/vc/local_source.hpp): the shipped model served in process
/// answers as the compensator does, refuses what the compensator refuses, and a model that
/// cannot be published is a ConfigError at construction.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/compensation_model_file.hpp>
#include <cmmcomp/status.hpp>
#include <cmmcomp/vc/length_test.hpp>
#include <cmmcomp/vc/local_source.hpp>
#include <limits>
#include <string>

namespace cmmcomp::vc {
namespace {

io::CompensationModelFile default_y() {
  return io::load_compensation_model(std::string(CMMCOMP_SOURCE_DIR) +
                                     "/data/models/default-y.json");
}

TEST(VcLocalSource, AnswersWithTheCorrectionAlongTheApproach) {
  const io::CompensationModelFile file = default_y();
  LocalSource source("5in", file, "default-y.json");
  EXPECT_EQ(source.label(), "5in");
  for (const Face face : {Face::kA, Face::kB}) {
    const compensation::MoveRequest m = request_for(default_fast_setting(), face, 250.0);
    const Answer a = source.ask(m);
    ASSERT_TRUE(a.usable) << a.note;
    EXPECT_EQ(a.status, static_cast<int>(Status::kOk));
    EXPECT_NE(a.flags & compensation::kFlagOk, 0u);
    EXPECT_EQ(a.model_id, io::numeric_model_id(file));
    // The correction is +RAE·d along X (docs/compensator.md), with the interval served.
    EXPECT_DOUBLE_EQ(a.correction_um[0], a.rae_um * direction_of(face));
    EXPECT_GT(a.u95_um[3], 0.0);
    EXPECT_TRUE(std::isfinite(a.rae_um));
  }
}

TEST(VcLocalSource, RefusesWhatTheCompensatorRefuses) {
  LocalSource source("5in", default_y(), "default-y.json");
  compensation::MoveRequest m = request_for(default_fast_setting(), Face::kA, 250.0);
  m.pv_mm_s = std::numeric_limits<double>::quiet_NaN();
  Answer a = source.ask(m);
  EXPECT_FALSE(a.usable);
  EXPECT_EQ(a.status, static_cast<int>(Status::kInvalidInput));
  EXPECT_EQ(a.flags, compensation::kFlagInvalidInput);
  EXPECT_FALSE(a.note.empty());
  // Far outside the training conditions (PA 1200 against 200): refused under every policy.
  m = request_for(default_fast_setting(), Face::kA, 250.0);
  m.pa_mm_s2 = 1200.0;
  a = source.ask(m);
  EXPECT_FALSE(a.usable);
  EXPECT_EQ(a.status, static_cast<int>(Status::kOutsideDomainRejected));
  // The request's axis has no model: only axis 0 was published.
  m = request_for(default_fast_setting(), Face::kA, 250.0);
  m.axis = 1;
  a = source.ask(m);
  EXPECT_FALSE(a.usable);
  EXPECT_EQ(a.status, static_cast<int>(Status::kNoModel));
}

TEST(VcLocalSource, AModelThatCannotBePublishedIsAConfigError) {
  EXPECT_THROW(LocalSource("x", default_y(), "default-y.json", 99), ConfigError);
}

}  // namespace
}  // namespace cmmcomp::vc
