// SPDX-License-Identifier: MIT
/// @file From a MoveRequest to the model's inputs, and from the model's outputs to a Correction.
///
/// Shared by every compensator (MoveCompensator on a hosted OS, StaticMoveCompensator on
/// firmware), so that the map between a move and a model is written once.
#pragma once

#include <array>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>

namespace cmmcomp::compensation {

/// Outputs of every compensation model, in this order (docs/compensator.md): MPE, RPE, MAE,
/// RAE [µm].
inline constexpr int kModelOutputs = 4;

/// True for the models a compensator serves: 3 sets or more per input, the four outputs, and
/// 4 inputs (PV, PD, AV, AD) or 5 (the same and the carriage position Y).
template <typename Model>
inline constexpr bool kIsCompensationModel = Model::Params::kOutputCount == kModelOutputs &&
                                             (Model::Params::kInputCount == 4 ||
                                              Model::Params::kInputCount == 5);

/// The model's raw inputs for `move`: (PV [mm/s], PD [mm], AV [mm/s], AD [mm]) and, for a
/// 5-input model, Y [mm]. RT-safe.
template <typename Model>
constexpr typename Model::RawInput model_input(const MoveRequest& move) noexcept {
  static_assert(kIsCompensationModel<Model>, "a compensation model has 4 or 5 inputs, 4 outputs");
  if constexpr (Model::Params::kInputCount == 5) {
    return {move.pv_mm_s, move.pd_mm, move.av_mm_s, move.ad_mm, move.y_mm};
  } else {
    return {move.pv_mm_s, move.pd_mm, move.av_mm_s, move.ad_mm};
  }
}

/// Writes the Correction of `move` from the model's outputs `y` (MPE, RPE, MAE, RAE, finite)
/// computed with status `s` (ok) by the model `model_id`: correction_um = RAE·d, and returns `s`.
/// RAE·d can overflow although RAE is finite (|d| may exceed 1 by kDirectionTolerance): then it
/// returns kInvalidInput and leaves `out` untouched, so a correction is never infinite. RT-safe.
[[nodiscard]] inline Status fill_correction(const MoveRequest& move,
                                            const std::array<double, kModelOutputs>& y,
                                            Status s,
                                            std::uint64_t model_id,
                                            Correction& out) noexcept {
  std::array<double, 3> correction{};
  bool finite = true;
  for (std::size_t k = 0; k < 3; ++k) {
    correction[k] = y[3] * move.direction[k];
    finite &= (correction[k] - correction[k]) == 0.0;  // false for ±inf (and NaN)
  }
  if (!finite) return Status::kInvalidInput;
  out.mpe_um = y[0];
  out.rpe_um = y[1];
  out.mae_um = y[2];
  out.rae_um = y[3];
  out.correction_um = correction;
  out.flags = flags_for(s);
  out.sequence = move.sequence;
  out.model_id = model_id;
  return s;
}

}  // namespace cmmcomp::compensation
