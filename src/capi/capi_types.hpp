// SPDX-License-Identifier: MIT
/// @file The C ABI's structs and codes as the C++ core's (include/cmmcomp/compensator.h): one
/// conversion, shared by the hosted ABI (compensator.cpp) and the firmware ABI
/// (compensator_fw.cpp). RT-safe.
#pragma once

#include <cmmcomp/compensator.h>

#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>

namespace cmmcomp::capi {

static_assert(CMMCOMP_MAX_AXES == static_cast<unsigned>(compensation::kMaxAxes), "axis count");
static_assert(CMMCOMP_E_INVALID_INPUT == static_cast<int>(Status::kInvalidInput), "codes");
static_assert(CMMCOMP_E_NO_MODEL == static_cast<int>(Status::kNoModel), "codes");
static_assert(CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED == static_cast<int>(Status::kOutsideDomainRejected),
              "codes");
static_assert(CMMCOMP_E_BUSY == static_cast<int>(Status::kBusy), "codes");
static_assert(CMMCOMP_FLAG_OK == compensation::kFlagOk &&
                  CMMCOMP_FLAG_OUTSIDE_DOMAIN == compensation::kFlagOutsideDomain &&
                  CMMCOMP_FLAG_INVALID_INPUT == compensation::kFlagInvalidInput &&
                  CMMCOMP_FLAG_NO_MODEL == compensation::kFlagNoModel &&
                  CMMCOMP_FLAG_NO_UNCERTAINTY == compensation::kFlagNoUncertainty,
              "flags");
static_assert(sizeof(cmmcomp_interval) == 4 * sizeof(double) + 2 * sizeof(std::uint32_t),
              "cmmcomp_interval has no padding: its layout is the ABI");
static_assert(offsetof(cmmcomp_interval, flags) == 4 * sizeof(double), "interval layout");

/// The core's request for `in`; the caller has checked in.axis < CMMCOMP_MAX_AXES.
inline compensation::MoveRequest to_move_request(const cmmcomp_move_request& in) noexcept {
  compensation::MoveRequest m;
  m.sequence = in.sequence;
  m.axis = static_cast<std::uint8_t>(in.axis);
  m.direction = {in.direction[0], in.direction[1], in.direction[2]};
  m.pv_mm_s = in.pv_mm_s;
  m.pa_mm_s2 = in.pa_mm_s2;
  m.pd_mm = in.pd_mm;
  m.av_mm_s = in.av_mm_s;
  m.aa_mm_s2 = in.aa_mm_s2;
  m.ad_mm = in.ad_mm;
  m.y_mm = in.y_mm;
  m.z_mm = in.z_mm;
  return m;
}

/// Writes the core's correction `r` into `out`.
inline void write_correction(const compensation::Correction& r, cmmcomp_correction& out) noexcept {
  out.mpe_um = r.mpe_um;
  out.rpe_um = r.rpe_um;
  out.mae_um = r.mae_um;
  out.rae_um = r.rae_um;
  for (std::size_t k = 0; k < 3; ++k) out.correction_um[k] = r.correction_um[k];
  // cmmcomp_correction predates the interval: its callers see the version-1 flags only.
  out.flags = r.flags & compensation::kFlagsVersion1;
  out.sequence = r.sequence;
  out.model_id = r.model_id;
}

/// Writes the interval of the core's correction `r` into `out`: every flag, U95 as computed.
inline void write_interval(const compensation::Correction& r, cmmcomp_interval& out) noexcept {
  for (std::size_t k = 0; k < 4; ++k) out.u95_um[k] = r.u95_um[k];
  out.flags = r.flags;
  out.reserved = 0;
}

}  // namespace cmmcomp::capi
