// SPDX-License-Identifier: MIT
/// @file The firmware C ABI (include/cmmcomp/compensator_fw.h) over
/// compensation::StaticMoveCompensator. Needs only the core: it builds for bare metal
/// (-fno-exceptions, newlib) as well as for a hosted test.
#include <cmmcomp/compensator_fw.h>

#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstddef>

#include "capi_types.hpp"

namespace {

// The C header names the input set by its size (compensator_fw.h: 4 = PV, PD, AV, AD; 5 = and Y).
#if CMMCOMP_FW_INPUTS == 5
using Inputs = cmmcomp::CarriageInputs;
#else
using Inputs = cmmcomp::PaperInputs;
#endif
using Model = cmmcomp::compensation::Model<Inputs, CMMCOMP_FW_SCALAR>;
static_assert(Inputs::kCount == CMMCOMP_FW_INPUTS, "the C header's input count");

// cmmcomp_fw_model is Model's layout spelled in C: the copy below relies on it.
static_assert(sizeof(cmmcomp_fw_model) == sizeof(Model), "cmmcomp_fw_model is TskModel's layout");
static_assert(offsetof(cmmcomp_fw_model, params) == offsetof(Model, params),
              "cmmcomp_fw_model is TskModel's layout");
static_assert(CMMCOMP_FW_PARAMS == Model::kParamCount, "parameter count");
static_assert(CMMCOMP_FW_RULES == Model::kRules, "rule count");
static_assert(sizeof(cmmcomp::fuzzy::InputRange) == 2 * sizeof(double), "ranges are {lo, hi}");

// cmmcomp_fw_interval_calibration is IntervalCalibration's layout spelled in C.
using Calibration = cmmcomp::compensation::IntervalCalibration;
static_assert(sizeof(cmmcomp_fw_interval_calibration) == sizeof(Calibration),
              "cmmcomp_fw_interval_calibration is IntervalCalibration's layout");
static_assert(sizeof(Calibration) == 13 * sizeof(double), "coverage and three arrays of 4");
static_assert(offsetof(cmmcomp_fw_interval_calibration, half_width) ==
                  offsetof(Calibration, half_width),
              "interval layout");
static_assert(offsetof(cmmcomp_fw_interval_calibration, extrapolation_gain) ==
                  offsetof(Calibration, extrapolation_gain),
              "interval layout");
static_assert(offsetof(cmmcomp_fw_interval_calibration, corner_gain) ==
                  offsetof(Calibration, corner_gain),
              "interval layout");

// cmmcomp_fw_conditions is Conditions' layout spelled in C.
using Conditions = cmmcomp::compensation::Conditions;
static_assert(sizeof(cmmcomp_fw_conditions) == sizeof(Conditions), "conditions layout");
static_assert(offsetof(cmmcomp_fw_conditions, aa_mm_s2) == offsetof(Conditions, aa_mm_s2),
              "conditions layout");

cmmcomp::compensation::StaticMoveCompensator<Model> g_compensator;

Conditions to_conditions(const cmmcomp_fw_conditions& c) noexcept {
  Conditions out;
  out.pa_mm_s2 = {c.pa_mm_s2[0], c.pa_mm_s2[1]};
  out.aa_mm_s2 = {c.aa_mm_s2[0], c.aa_mm_s2[1]};
  return out;
}

Calibration to_calibration(const cmmcomp_fw_interval_calibration& c) noexcept {
  Calibration out;
  out.coverage = c.coverage;
  for (std::size_t o = 0; o < 4; ++o) {
    out.half_width[o] = c.half_width[o];
    out.extrapolation_gain[o] = c.extrapolation_gain[o];
    out.corner_gain[o] = c.corner_gain[o];
  }
  return out;
}

int publish_code(cmmcomp::Status s) noexcept {
  if (s == cmmcomp::Status::kInvalidInput) return CMMCOMP_E_MODEL;
  return static_cast<int>(s);
}

}  // namespace

extern "C" {

int cmmcomp_fw_set_outside_domain(int policy) {
  if (policy < 0 || policy > 2) return CMMCOMP_E_ARGUMENT;
  return g_compensator.set_outside_domain(static_cast<cmmcomp::fuzzy::DomainPolicy>(policy))
             ? CMMCOMP_OK
             : CMMCOMP_E_ARGUMENT;
}

int cmmcomp_fw_publish(uint32_t axis, const cmmcomp_fw_model* model, uint64_t model_id) {
  if (model == nullptr || axis >= CMMCOMP_MAX_AXES) return CMMCOMP_E_ARGUMENT;
  return publish_code(
      g_compensator.publish_bytes(static_cast<int>(axis), model, sizeof *model, model_id));
}

int cmmcomp_fw_publish_with_interval(uint32_t axis,
                                     const cmmcomp_fw_model* model,
                                     const cmmcomp_fw_interval_calibration* interval,
                                     uint64_t model_id) {
  if (model == nullptr || interval == nullptr || axis >= CMMCOMP_MAX_AXES) {
    return CMMCOMP_E_ARGUMENT;
  }
  return publish_code(g_compensator.publish_bytes(
      static_cast<int>(axis), model, sizeof *model, to_calibration(*interval), model_id));
}

int cmmcomp_fw_publish_with_conditions(uint32_t axis,
                                       const cmmcomp_fw_model* model,
                                       const cmmcomp_fw_interval_calibration* interval,
                                       const cmmcomp_fw_conditions* conditions,
                                       uint64_t model_id) {
  if (model == nullptr || conditions == nullptr || axis >= CMMCOMP_MAX_AXES) {
    return CMMCOMP_E_ARGUMENT;
  }
  const Calibration calibration = interval != nullptr ? to_calibration(*interval) : Calibration{};
  return publish_code(g_compensator.publish_bytes(static_cast<int>(axis),
                                                  model,
                                                  sizeof *model,
                                                  calibration,
                                                  to_conditions(*conditions),
                                                  model_id));
}

int cmmcomp_fw_before_approach(const cmmcomp_move_request* in, cmmcomp_correction* out) {
  if (in == nullptr || out == nullptr) return CMMCOMP_E_ARGUMENT;
  if (in->axis >= CMMCOMP_MAX_AXES) return CMMCOMP_E_INVALID_INPUT;
  cmmcomp::compensation::Correction r;
  const cmmcomp::Status s = g_compensator.before_approach(cmmcomp::capi::to_move_request(*in), r);
  if (!cmmcomp::ok(s)) return static_cast<int>(s);
  cmmcomp::capi::write_correction(r, *out);
  return CMMCOMP_OK;
}

int cmmcomp_fw_before_approach_with_interval(const cmmcomp_move_request* in,
                                             cmmcomp_correction* out,
                                             cmmcomp_interval* interval) {
  if (in == nullptr || out == nullptr || interval == nullptr) return CMMCOMP_E_ARGUMENT;
  if (in->axis >= CMMCOMP_MAX_AXES) return CMMCOMP_E_INVALID_INPUT;
  cmmcomp::compensation::Correction r;
  const cmmcomp::Status s = g_compensator.before_approach(cmmcomp::capi::to_move_request(*in), r);
  if (!cmmcomp::ok(s)) return static_cast<int>(s);
  cmmcomp::capi::write_correction(r, *out);
  cmmcomp::capi::write_interval(r, *interval);
  return CMMCOMP_OK;
}

}  // extern "C"
