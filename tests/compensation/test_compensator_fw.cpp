// SPDX-License-Identifier: MIT
/// @file The firmware C ABI (cmmcomp/compensator_fw.h): the shipped model exported as C source
/// (data/models/default-float.c) answers exactly as the C++ StaticMoveCompensator serving the
/// constexpr header converted to float, its interval included; bad models, calibrations and
/// requests give codes and keep the old model.
#include <cmmcomp/compensator_fw.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstring>
#include <limits>
#include <random>

#include "capi/capi_types.hpp"
#include "default.hpp"
#include "support/test_seed.hpp"

extern "C" const cmmcomp_fw_model default_model_c;
extern "C" const uint64_t default_model_c_id;
extern "C" const cmmcomp_fw_interval_calibration default_model_c_interval;
extern "C" const cmmcomp_fw_conditions default_model_c_conditions;

namespace {

using ModelF = cmmcomp::compensation::Model<cmmcomp::PaperInputs, float>;
cmmcomp::compensation::StaticMoveCompensator<ModelF> g_reference;

cmmcomp_move_request random_request(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  cmmcomp_move_request r{};
  r.sequence = static_cast<uint32_t>(rng());
  r.axis = static_cast<uint32_t>(rng() % CMMCOMP_MAX_AXES);
  r.direction[2] = -1.0;
  r.pv_mm_s = 30.0 + 80.0 * u(rng);
  r.pa_mm_s2 = 200.0;
  r.pd_mm = 35.0 + 50.0 * u(rng);
  r.av_mm_s = 6.0 + 12.0 * u(rng);
  r.aa_mm_s2 = 60.0;
  r.ad_mm = 4.0 + 12.0 * u(rng);
  return r;
}

// One test, because the C ABI has one compensator: the order of these steps matters.
TEST(CompensatorFw, ServesTheExportedModelExactlyAsTheCppCompensator) {
  cmmcomp_move_request request{};
  cmmcomp_correction out{};
  std::mt19937_64 rng(cmmcomp::test::seed());
  request = random_request(rng);
  EXPECT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_E_NO_MODEL);
  EXPECT_EQ(cmmcomp_fw_set_outside_domain(7), CMMCOMP_E_ARGUMENT);
  EXPECT_EQ(cmmcomp_fw_set_outside_domain(0), CMMCOMP_OK);  // before the first publish
  EXPECT_EQ(cmmcomp_fw_publish(CMMCOMP_MAX_AXES, &default_model_c, 1), CMMCOMP_E_ARGUMENT);
  EXPECT_EQ(cmmcomp_fw_publish(0, nullptr, 1), CMMCOMP_E_ARGUMENT);
  for (uint32_t axis = 0; axis < CMMCOMP_MAX_AXES; ++axis) {
    ASSERT_EQ(cmmcomp_fw_publish(axis, &default_model_c, default_model_c_id), CMMCOMP_OK);
    ASSERT_EQ(g_reference.publish(static_cast<int>(axis),
                                  cmmcomp::fuzzy::convert_model<float>(default_model),
                                  default_model_c_id),
              cmmcomp::Status::kOk);
  }
  EXPECT_EQ(cmmcomp_fw_set_outside_domain(1), CMMCOMP_E_ARGUMENT);  // fixed once published
  for (int k = 0; k < 2000; ++k) {
    request = random_request(rng);
    cmmcomp::compensation::Correction expected;
    const cmmcomp::Status s =
        g_reference.before_approach(cmmcomp::capi::to_move_request(request), expected);
    const int code = cmmcomp_fw_before_approach(&request, &out);
    ASSERT_EQ(code, cmmcomp::ok(s) ? 0 : static_cast<int>(s)) << "move " << k;
    if (code != 0) continue;
    EXPECT_EQ(std::memcmp(&out.rae_um, &expected.rae_um, sizeof(double)), 0) << "move " << k;
    EXPECT_EQ(std::memcmp(&out.mpe_um, &expected.mpe_um, sizeof(double)), 0) << "move " << k;
    EXPECT_EQ(out.correction_um[2], -expected.rae_um);
    // The C structs carry the version-1 flags (compensator.h); the C++ one adds the interval's.
    EXPECT_EQ(out.flags, expected.flags & cmmcomp::compensation::kFlagsVersion1);
    EXPECT_EQ(out.model_id, default_model_c_id);
    EXPECT_EQ(out.sequence, request.sequence);
  }
  // A corrupt model is refused; the one published keeps serving.
  static cmmcomp_fw_model corrupt;
  std::memcpy(&corrupt, &default_model_c, sizeof corrupt);
  corrupt.params[2 * 3 * 4 + 5] = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(cmmcomp_fw_publish(1, &corrupt, 99), CMMCOMP_E_MODEL);
  std::memcpy(&corrupt, &default_model_c, sizeof corrupt);
  corrupt.params[4 * 3 + 1] = -0.5f;  // a width
  EXPECT_EQ(cmmcomp_fw_publish(1, &corrupt, 98), CMMCOMP_E_MODEL);
  request = random_request(rng);
  request.axis = 1;
  ASSERT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_OK);
  EXPECT_EQ(out.model_id, default_model_c_id);
  // Bad requests.
  EXPECT_EQ(cmmcomp_fw_before_approach(nullptr, &out), CMMCOMP_E_ARGUMENT);
  EXPECT_EQ(cmmcomp_fw_before_approach(&request, nullptr), CMMCOMP_E_ARGUMENT);
  request.axis = CMMCOMP_MAX_AXES;
  EXPECT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_E_INVALID_INPUT);
  request.axis = 0;
  request.pv_mm_s = std::nan("");
  EXPECT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_E_INVALID_INPUT);

  // The interval (docs/uncertainty.md). The exported calibration is the C++ header's, value for
  // value; a model published without one answers "no uncertainty".
  static_assert(sizeof(cmmcomp_fw_interval_calibration) == sizeof(default_model_interval), "");
  EXPECT_EQ(std::memcmp(
                &default_model_c_interval, &default_model_interval, sizeof default_model_interval),
            0);
  ASSERT_TRUE(default_model_interval.available());
  cmmcomp_interval interval{};
  request = random_request(rng);
  request.axis = 0;
  ASSERT_EQ(cmmcomp_fw_before_approach_with_interval(&request, &out, &interval), CMMCOMP_OK);
  EXPECT_NE(interval.flags & CMMCOMP_FLAG_NO_UNCERTAINTY, 0u);
  EXPECT_EQ(interval.u95_um[3], 0.0);
  EXPECT_EQ(cmmcomp_fw_publish_with_interval(0, &default_model_c, nullptr, 1), CMMCOMP_E_ARGUMENT);
  EXPECT_EQ(cmmcomp_fw_publish_with_interval(0, nullptr, &default_model_c_interval, 1),
            CMMCOMP_E_ARGUMENT);
  for (uint32_t axis = 0; axis < CMMCOMP_MAX_AXES; ++axis) {
    ASSERT_EQ(cmmcomp_fw_publish_with_interval(
                  axis, &default_model_c, &default_model_c_interval, default_model_c_id),
              CMMCOMP_OK);
    ASSERT_EQ(g_reference.publish(static_cast<int>(axis),
                                  cmmcomp::fuzzy::convert_model<float>(default_model),
                                  default_model_interval,
                                  default_model_c_id),
              cmmcomp::Status::kOk);
  }
  int grown = 0;
  for (int k = 0; k < 2000; ++k) {
    request = random_request(rng);
    cmmcomp::compensation::Correction expected;
    const cmmcomp::Status s =
        g_reference.before_approach(cmmcomp::capi::to_move_request(request), expected);
    const int code = cmmcomp_fw_before_approach_with_interval(&request, &out, &interval);
    ASSERT_EQ(code, cmmcomp::ok(s) ? 0 : static_cast<int>(s)) << "move " << k;
    if (code != 0) continue;
    EXPECT_EQ(std::memcmp(interval.u95_um, expected.u95_um.data(), sizeof interval.u95_um), 0)
        << "move " << k;
    EXPECT_EQ(interval.flags, expected.flags);
    EXPECT_EQ(interval.flags & CMMCOMP_FLAG_NO_UNCERTAINTY, 0u);
    EXPECT_EQ(std::memcmp(&out.rae_um, &expected.rae_um, sizeof(double)), 0) << "move " << k;
    grown += interval.u95_um[3] > default_model_interval.half_width[3] ? 1 : 0;
  }
  EXPECT_GT(grown, 1000) << "most random moves are off-centre or outside: U95 grows";
  // A bad calibration is refused; the model and calibration published keep serving.
  cmmcomp_fw_interval_calibration bad = default_model_c_interval;
  bad.corner_gain[1] = -1.0;
  EXPECT_EQ(cmmcomp_fw_publish_with_interval(2, &default_model_c, &bad, 97), CMMCOMP_E_MODEL);
  bad = default_model_c_interval;
  bad.half_width[3] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(cmmcomp_fw_publish_with_interval(2, &default_model_c, &bad, 96), CMMCOMP_E_MODEL);
  bad = default_model_c_interval;
  bad.coverage = 0.0;  // values without a coverage
  EXPECT_EQ(cmmcomp_fw_publish_with_interval(2, &default_model_c, &bad, 95), CMMCOMP_E_MODEL);
  request = random_request(rng);
  request.axis = 2;
  ASSERT_EQ(cmmcomp_fw_before_approach_with_interval(&request, &out, &interval), CMMCOMP_OK);
  EXPECT_EQ(out.model_id, default_model_c_id);
  EXPECT_EQ(interval.flags & CMMCOMP_FLAG_NO_UNCERTAINTY, 0u);
  EXPECT_EQ(cmmcomp_fw_before_approach_with_interval(&request, &out, nullptr), CMMCOMP_E_ARGUMENT);

  // The training conditions (docs/compensator.md, "Domain"): the C source's are the header's,
  // the model's PA 200 and AA 60 mm/s².
  static_assert(sizeof(cmmcomp_fw_conditions) == sizeof(default_model_conditions), "");
  EXPECT_EQ(
      std::memcmp(
          &default_model_c_conditions, &default_model_conditions, sizeof default_model_conditions),
      0);
  EXPECT_EQ(default_model_c_conditions.pa_mm_s2[0], 200.0);
  EXPECT_EQ(default_model_c_conditions.aa_mm_s2[1], 60.0);
  EXPECT_EQ(cmmcomp_fw_publish_with_conditions(3, &default_model_c, nullptr, nullptr, 1),
            CMMCOMP_E_ARGUMENT);
  cmmcomp_fw_conditions bad_conditions = default_model_c_conditions;
  bad_conditions.pa_mm_s2[0] = 300.0;  // lo > hi
  EXPECT_EQ(cmmcomp_fw_publish_with_conditions(
                3, &default_model_c, &default_model_c_interval, &bad_conditions, 94),
            CMMCOMP_E_MODEL);
  ASSERT_EQ(cmmcomp_fw_publish_with_conditions(3,
                                               &default_model_c,
                                               &default_model_c_interval,
                                               &default_model_c_conditions,
                                               default_model_c_id),
            CMMCOMP_OK);
  request = random_request(rng);
  request.axis = 3;
  request.pv_mm_s = 70.0;  // inside the box (L18's): only the accelerations decide
  request.pd_mm = 60.0;
  request.av_mm_s = 12.0;
  request.ad_mm = 10.0;
  ASSERT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_OK);
  EXPECT_EQ(out.flags, CMMCOMP_FLAG_OK);
  request.pa_mm_s2 = 210.0;  // outside the trained PA, not far: flagged
  ASSERT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_OK);
  EXPECT_EQ(out.flags, CMMCOMP_FLAG_OK | CMMCOMP_FLAG_OUTSIDE_DOMAIN);
  request.pa_mm_s2 = 1200.0;  // far outside: refused under the clamp policy too
  EXPECT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED);
  request.pa_mm_s2 = 200.0;
  request.aa_mm_s2 = 300.0;
  EXPECT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED);
  request.axis = 2;  // published without conditions: the accelerations are not checked
  ASSERT_EQ(cmmcomp_fw_before_approach(&request, &out), CMMCOMP_OK);
  EXPECT_EQ(out.flags, CMMCOMP_FLAG_OK);
}

}  // namespace
