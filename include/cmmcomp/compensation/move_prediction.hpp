// SPDX-License-Identifier: MIT
/// @file The compensation model (a network keyed on its input set), and from its outputs to a
/// Correction.
///
/// Shared by every compensator (MoveCompensator on a hosted OS, StaticMoveCompensator on
/// firmware), so that the map between a move and a model is written once.
#pragma once

#include <array>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/fuzzy/prediction_interval.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace cmmcomp::compensation {

/// Outputs of every compensation model, in the order of schema.hpp's kErrors: MPE, RPE, MAE,
/// RAE [µm] (docs/compensator.md).
inline constexpr int kModelOutputs = kErrorCount;
/// Gaussian sets per input of every compensation model (the paper's 3: low, medium, high).
inline constexpr int kSetsPerInput = 3;

/// A compensation model: the T-S network of `InputsT` (a schema InputSet) with 3 sets per input
/// and the four error parameters as outputs, in precision `Scalar` (double, or float for an
/// MCU). It IS the network (fuzzy::evaluate and fuzzy::validate take it as such) and carries
/// its input set in its type, so a compensator gathers the right inputs from each MoveRequest
/// and a model with other inputs cannot be published in its place.
template <typename InputsT, typename Scalar = double>
struct Model : fuzzy::TskModel<Scalar, InputsT::kCount, kSetsPerInput, kModelOutputs> {
  using Inputs = InputsT;
  using Network = fuzzy::TskModel<Scalar, InputsT::kCount, kSetsPerInput, kModelOutputs>;

  Model() = default;
  /// The model of a network trained on `Inputs` (e.g. one exported as a constexpr header).
  constexpr explicit Model(const Network& network) noexcept : Network(network) {}

  /// The network's raw inputs for `move`, in the set's order. RT-safe.
  static constexpr typename Network::RawInput input(const MoveRequest& move) noexcept {
    return Inputs::gather(move);
  }
};

/// The interval calibration of a compensation model (fuzzy/prediction_interval.hpp). It is
/// published with the model into the same buffer (so a hot swap changes both at once) and is
/// not part of Model itself: Model's layout is the firmware C ABI's cmmcomp_fw_model.
using IntervalCalibration = fuzzy::IntervalCalibration<kModelOutputs>;

/// The interval half-widths [µm] of `move` under `model` with calibration `interval`: the
/// distance and the corner share are taken from the move's inputs as given (before any
/// clamping). RT-safe.
template <typename M>
inline std::array<double, kModelOutputs> interval_of(const M& model,
                                                     const IntervalCalibration& interval,
                                                     const MoveRequest& move) noexcept {
  std::array<double, kModelOutputs> u{};
  if (interval.available()) {
    fuzzy::interval_half_widths_at(interval, model.ranges, M::input(move), u);
  }
  return u;
}

/// True when `M` is a compensation::Model (of any input set and precision).
template <typename M, typename = void>
inline constexpr bool kIsCompensationModel = false;
template <typename M>
inline constexpr bool kIsCompensationModel<M, std::void_t<typename M::Inputs>> =
    std::is_base_of_v<typename M::Network, M>&& M::Network::Params::kInputCount ==
    M::Inputs::kCount;

static_assert(kErrors[0].correction == &Correction::mpe_um &&
                  kErrors[1].correction == &Correction::rpe_um &&
                  kErrors[2].correction == &Correction::mae_um &&
                  kErrors[3].correction == &Correction::rae_um,
              "fill_correction writes the outputs in schema.hpp's kErrors order");

/// Writes the Correction of `move` from the model's outputs `y` (MPE, RPE, MAE, RAE, finite)
/// and interval half-widths `u95` (interval_of) computed with status `s` (ok) by the model
/// `model_id` (`has_interval`: its calibration is available): correction_um = RAE·d, and
/// returns `s`.
/// RAE·d can overflow although RAE is finite (|d| may exceed 1 by kDirectionTolerance): then it
/// returns kInvalidInput and leaves `out` untouched, so a correction is never infinite. RT-safe.
[[nodiscard]] inline Status fill_correction(const MoveRequest& move,
                                            const std::array<double, kModelOutputs>& y,
                                            const std::array<double, kModelOutputs>& u95,
                                            bool has_interval,
                                            Status s,
                                            std::uint64_t model_id,
                                            Correction& out) noexcept {
  constexpr auto kRae = static_cast<std::size_t>(ErrorParameter::kRae);
  std::array<double, 3> correction{};
  bool finite = true;
  for (std::size_t k = 0; k < 3; ++k) {
    correction[k] = y[kRae] * move.direction[k];
    finite &= (correction[k] - correction[k]) == 0.0;  // false for ±inf (and NaN)
  }
  if (!finite) return Status::kInvalidInput;
  // Field by field, not through kErrors' member pointers: the same stores, but GCC -O2 keeps
  // the pointer loop on Cortex-M7 (+54 instructions per call). The static_asserts above tie
  // the order to the schema.
  out.mpe_um = y[0];
  out.rpe_um = y[1];
  out.mae_um = y[2];
  out.rae_um = y[3];
  out.correction_um = correction;
  out.u95_um = u95;
  out.flags = flags_for(s) | (has_interval ? 0u : static_cast<std::uint32_t>(kFlagNoUncertainty));
  out.sequence = move.sequence;
  out.model_id = model_id;
  return s;
}

}  // namespace cmmcomp::compensation
