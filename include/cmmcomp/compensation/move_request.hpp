// SPDX-License-Identifier: MIT
/// @file One probing move as the controller announces it, and the correction it gets back.
///
/// Units follow the trained model (docs/compensator.md): lengths in mm, speeds in mm/s,
/// accelerations in mm/s², errors and corrections in µm. The unit is in every field name, as in
/// the C ABI (include/cmmcomp/compensator.h), because these values cross into controller code.
#pragma once

#include <array>
#include <cmath>
#include <cmmcomp/status.hpp>
#include <cstdint>

namespace cmmcomp::compensation {

/// Axes a MoveCompensator serves (one model slot each): X, Y, Z and one spare (e.g. a rotary
/// table or a second ram).
inline constexpr int kMaxAxes = 4;

/// Tolerance on |direction| = 1 accepted by `validate_move`.
inline constexpr double kDirectionTolerance = 1e-6;

/// One probing move, announced before its approach (docs/dynamic-errors.md for PV … AD).
struct MoveRequest {
  std::uint32_t sequence = 0;  ///< echoed in the Correction, to pair requests and answers
  std::uint8_t axis = 0;       ///< moving axis, 0 .. kMaxAxes−1; selects the model slot
  /// Approach direction in machine coordinates: the unit vector d along which the probe moves
  /// towards the part (finite, |d| = 1 ± kDirectionTolerance). The correction is RAE·d.
  std::array<double, 3> direction{1.0, 0.0, 0.0};
  double pv_mm_s = 0.0;  ///< positioning speed PV [mm/s], > 0
  /// positioning acceleration PA [mm/s²], > 0 (validated, not an input of the served models)
  double pa_mm_s2 = 0.0;
  double pd_mm = 0.0;     ///< positioning distance PD [mm], > 0
  double av_mm_s = 0.0;   ///< approach speed AV [mm/s], > 0
  double aa_mm_s2 = 0.0;  ///< approach acceleration AA [mm/s²], > 0 (validated, not a model input)
  double ad_mm = 0.0;     ///< approach distance AD [mm], > 0
  double y_mm = 0.0;      ///< carriage position [mm], finite (not an input of the 4-input model)
  double z_mm = 0.0;      ///< ram position [mm], finite (not an input of the 4-input model)
};

/// Bits of Correction::flags.
enum CorrectionFlag : std::uint32_t {
  kFlagOk = 1u << 0,             ///< the correction is valid and may be applied
  kFlagOutsideDomain = 1u << 1,  ///< an input was outside the training ranges; policy applied
  kFlagInvalidInput = 1u << 2,   ///< the request was rejected (NaN, inf, ≤ 0, bad axis/direction)
  kFlagNoModel = 1u << 3,        ///< no model published for the axis
  /// The model carries no interval calibration (a format-version-1 file, or a model built in
  /// code): Correction::u95_um is 0 and means "unknown", not "exact" (docs/uncertainty.md).
  kFlagNoUncertainty = 1u << 4,
};

/// The CorrectionFlag bits of protocol version 1 (CAN, Modbus): what a client written before
/// the interval knew. The wire formats carry only these until their version 2.
inline constexpr std::uint32_t kFlagsVersion1 =
    kFlagOk | kFlagOutsideDomain | kFlagInvalidInput | kFlagNoModel;

/// The flags that describe `s`, for a caller that reports failures through a Correction (the
/// compensator itself writes a Correction only when ok(s)). RT-safe.
constexpr std::uint32_t flags_for(Status s) noexcept {
  switch (s) {
    case Status::kOk:
      return kFlagOk;
    case Status::kOutsideDomain:
      return kFlagOk | kFlagOutsideDomain;
    case Status::kOutsideDomainRejected:
      return kFlagOutsideDomain;
    case Status::kNoModel:
      return kFlagNoModel;
    default:
      return kFlagInvalidInput;
  }
}

/// The predicted errors of one move and the correction of its touch point.
struct Correction {
  double mpe_um = 0.0;  ///< predicted maximum positioning error MPE [µm] (magnitude)
  double rpe_um = 0.0;  ///< predicted residual positioning error RPE [µm], + = tip ahead
  double mae_um = 0.0;  ///< predicted maximum approach error MAE [µm] (magnitude)
  double rae_um = 0.0;  ///< predicted residual approach error RAE [µm], + = tip ahead
  /// Correction of the touch point [µm], machine coordinates: +RAE·d. The controller ADDS it to
  /// the scale-reported touch point (docs/compensator.md, "Signs").
  std::array<double, 3> correction_um{0.0, 0.0, 0.0};
  /// Half-width of the prediction interval of each predicted error [µm], in schema.hpp's
  /// kErrors order (MPE, RPE, MAE, RAE): the measured error lies within predicted ± u95 with the
  /// model's calibrated coverage: 95 % for every model a file loads (io::publish, and every
  /// interface over it, refuses a file calibrated at another coverage); a caller that publishes
  /// an IntervalCalibration itself has its coverage in IntervalCalibration::coverage. It grows with
  /// the move's distance outside the training ranges, whatever the domain policy. 0 with
  /// kFlagNoUncertainty when the model has no calibration. docs/uncertainty.md.
  std::array<double, 4> u95_um{0.0, 0.0, 0.0, 0.0};
  std::uint32_t flags = 0;     ///< CorrectionFlag bits
  std::uint32_t sequence = 0;  ///< MoveRequest::sequence echoed
  std::uint64_t model_id = 0;  ///< id of the model that computed it (first 16 hex of checksum)
};

/// Checks a request: axis < kMaxAxes; PV, PA, PD, AV, AA, AD finite and > 0; y, z finite;
/// direction finite with |d| = 1 ± kDirectionTolerance. Returns kOk or kInvalidInput. RT-safe.
[[nodiscard]] inline Status validate_move(const MoveRequest& m) noexcept {
  if (m.axis >= kMaxAxes) return Status::kInvalidInput;
  const double positive[6] = {m.pv_mm_s, m.pa_mm_s2, m.pd_mm, m.av_mm_s, m.aa_mm_s2, m.ad_mm};
  bool good = true;
  for (double v : positive) good = good && std::isfinite(v) && v > 0.0;
  good = good && std::isfinite(m.y_mm) && std::isfinite(m.z_mm);
  double norm2 = 0.0;
  for (double c : m.direction) {
    good = good && std::isfinite(c);
    norm2 += c * c;
  }
  // |d|² within (1 ± tol)²; computed on the square to avoid a sqrt.
  const double lo = (1.0 - kDirectionTolerance) * (1.0 - kDirectionTolerance);
  const double hi = (1.0 + kDirectionTolerance) * (1.0 + kDirectionTolerance);
  good = good && norm2 >= lo && norm2 <= hi;
  return good ? Status::kOk : Status::kInvalidInput;
}

}  // namespace cmmcomp::compensation
