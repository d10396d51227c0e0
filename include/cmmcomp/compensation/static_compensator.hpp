// SPDX-License-Identifier: MIT
/// @file The compensator for firmware without an OS: static storage, no heap, no thread, no lock.
///
/// `StaticMoveCompensator<Model>` serves one model type (a compensation::Model of one input
/// set, double or float: see fuzzy::convert_model) on up to kMaxAxes axes. It needs nothing but
/// C++17 and lock-free 32-bit atomics, so it builds with arm-none-eabi-g++ and newlib,
/// -fno-exceptions -fno-rtti, and can live in .bss (`static StaticMoveCompensator<M>
/// compensator;`). Every member is noexcept and allocation-free, publish included.
///
/// Threading contract (docs/firmware.md, "Hot swap without an OS"): ONE publisher (the main loop
/// or a low-priority task) and any number of readers that PREEMPT it: interrupt handlers, or
/// tasks of higher priority on the same core, which run `before_approach` to completion before
/// the publisher resumes. This is the MCU counterpart of MoveCompensator's hosted scheme, and
/// it is what lets publish never wait:
///  - each axis has two buffers and a 32-bit word `current`: 0 before the first publish, else
///    1 + the index of the buffer serving (so that a compensator is all zeros, and a static one
///    lives in .bss, not in .data where its buffers would take flash as well as RAM);
///  - a reader loads `current`, counts itself into that buffer's `readers`, evaluates, and
///    counts itself out: two single-word atomic RMWs (LDREX/STREX on ARMv7-M), no loop of ours;
///  - publish fills the buffer that is NOT current, then stores its index into `current`. The
///    buffer it fills was current only before the previous publish; every reader that could have
///    entered it has run to completion since, because readers preempt the publisher. So publish
///    never overwrites a buffer in use, and never needs to wait.
///  - If the contract is broken (a reader at lower priority than the publisher, or on another
///    core), a reader may still be inside the free buffer. publish checks its `readers` count
///    first and returns Status::kBusy without touching anything; the old model keeps serving.
///    The check is a safety net, not the guarantee: a reader preempted between loading
///    `current` and counting itself in is not seen. On a multi-core MCU use one compensator per
///    core, or MoveCompensator's scheme.
#pragma once

#include <array>
#include <atomic>
#include <cmmcomp/compensation/conditions.hpp>
#include <cmmcomp/compensation/move_prediction.hpp>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <type_traits>

namespace cmmcomp::compensation {

/// A compensator with static storage for one model type `ModelT` (compensation::Model<Inputs,
/// Scalar>: the network of one input set with the outputs MPE, RPE, MAE, RAE) on `kAxes` axes;
/// see the file comment.
template <typename ModelT, int kAxes = kMaxAxes>
class StaticMoveCompensator {
  static_assert(kIsCompensationModel<ModelT>, "ModelT is a compensation::Model<Inputs, Scalar>");
  static_assert(sizeof(ModelT) == sizeof(typename ModelT::Network),
                "a Model is its network: publish copies a network's bytes into it");
  static_assert(kAxes > 0 && kAxes <= kMaxAxes, "MoveRequest::axis selects one of kMaxAxes axes");
  static_assert(std::atomic<std::uint32_t>::is_always_lock_free,
                "the RT path needs lock-free 32-bit atomics");

 public:
  using Model = ModelT;
  using Network = typename Model::Network;  ///< what an exported model header defines

  /// A compensator with no model on any axis; `outside_domain` is what before_approach does
  /// with a move outside the model's training ranges (default kClamp, as MoveCompensator).
  /// An `outside_domain` that is not a DomainPolicy value makes every before_approach return
  /// kInvalidInput (fuzzy::evaluate checks it).
  constexpr explicit StaticMoveCompensator(
      fuzzy::DomainPolicy outside_domain = fuzzy::DomainPolicy::kClamp) noexcept
      : outside_domain_(outside_domain) {}
  StaticMoveCompensator(const StaticMoveCompensator&) = delete;
  StaticMoveCompensator& operator=(const StaticMoveCompensator&) = delete;

  /// The outside-domain policy.
  fuzzy::DomainPolicy outside_domain() const noexcept { return outside_domain_; }

  /// Changes the outside-domain policy; only before the first publish, when no reader reads it
  /// (they stop at kNoModel). Publisher only. Returns false, changing nothing, afterwards.
  bool set_outside_domain(fuzzy::DomainPolicy policy) noexcept {
    if (published_) return false;
    outside_domain_ = policy;
    return true;
  }

  /// Makes `model` (a network trained on Model::Inputs, e.g. a constexpr exported header's, or
  /// a Model) the model of `axis` for every before_approach call that starts after this
  /// returns. Publisher only (one at a time; see the threading contract). Copies the model
  /// (sizeof(Model) bytes) into the axis' free buffer: bounded time, no allocation, no wait.
  /// Returns kOk; kInvalidInput when `axis` is out of range or fuzzy::find_problem(model) finds
  /// a problem (`problem`, if given, says which); kBusy when a reader is still inside the free
  /// buffer (the contract is broken). On any error nothing changes: the old model keeps serving.
  Status publish(int axis,
                 const Network& model,
                 std::uint64_t model_id = 0,
                 fuzzy::ModelProblem* problem = nullptr) noexcept {
    return publish(axis, model, IntervalCalibration{}, model_id, problem);
  }

  /// The same, with the model's interval calibration: every Correction it computes carries
  /// u95_um. kInvalidInput also when fuzzy::interval_is_valid(interval) is false.
  Status publish(int axis,
                 const Network& model,
                 const IntervalCalibration& interval,
                 std::uint64_t model_id = 0,
                 fuzzy::ModelProblem* problem = nullptr) noexcept {
    return publish(axis, model, interval, Conditions{}, model_id, problem);
  }

  /// The same, with the accelerations the model was trained at (conditions.hpp): a move
  /// outside them is flagged or refused. kInvalidInput also when `conditions` is not valid.
  Status publish(int axis,
                 const Network& model,
                 const IntervalCalibration& interval,
                 const Conditions& conditions,
                 std::uint64_t model_id = 0,
                 fuzzy::ModelProblem* problem = nullptr) noexcept {
    if (axis < 0 || axis >= kAxes) return Status::kInvalidInput;
    if (!fuzzy::interval_is_valid(interval) || !conditions_are_valid(conditions)) {
      return Status::kInvalidInput;
    }
    const fuzzy::ModelProblem found = fuzzy::find_problem(model);
    if (problem != nullptr) *problem = found;
    if (found) return Status::kInvalidInput;
    Axis& a = axes_[static_cast<std::size_t>(axis)];
    // The buffer not serving (buffer 0 at the first publish).
    const std::uint32_t next = a.current.load(std::memory_order_relaxed) == 1 ? 1 : 0;
    Buffer& b = a.buffers[next];
    if (b.readers.load(std::memory_order_acquire) != 0) return Status::kBusy;
    // A byte copy of the network into the Model (which is nothing but the network) starts the
    // member's lifetime, as the trivial copy of publish_bytes does.
    std::memcpy(static_cast<void*>(&b.slot.model), &model, sizeof(Model));
    b.interval = interval;
    b.conditions = conditions;
    b.model_id = model_id;
    published_ = true;
    a.current.store(next + 1, std::memory_order_release);
    return Status::kOk;
  }

  /// The same for a model given as `size` bytes of Model's object representation (the C ABI's
  /// cmmcomp_fw_model, compensator_fw.h): copied straight into the free buffer, checked there
  /// (find_problem), and published only if it passes. No staging copy on the stack.
  Status publish_bytes(int axis,
                       const void* bytes,
                       std::size_t size,
                       std::uint64_t model_id = 0,
                       fuzzy::ModelProblem* problem = nullptr) noexcept {
    return publish_bytes(axis, bytes, size, IntervalCalibration{}, model_id, problem);
  }

  /// The same, with the model's interval calibration (published with it into the same buffer).
  /// kInvalidInput also when fuzzy::interval_is_valid(interval) is false.
  Status publish_bytes(int axis,
                       const void* bytes,
                       std::size_t size,
                       const IntervalCalibration& interval,
                       std::uint64_t model_id = 0,
                       fuzzy::ModelProblem* problem = nullptr) noexcept {
    return publish_bytes(axis, bytes, size, interval, Conditions{}, model_id, problem);
  }

  /// The same, with the model's training conditions (published with it into the same buffer).
  /// kInvalidInput also when `conditions` is not valid (conditions_are_valid).
  Status publish_bytes(int axis,
                       const void* bytes,
                       std::size_t size,
                       const IntervalCalibration& interval,
                       const Conditions& conditions,
                       std::uint64_t model_id = 0,
                       fuzzy::ModelProblem* problem = nullptr) noexcept {
    static_assert(std::is_trivially_copyable_v<Model>, "a model is plain bytes");
    if (axis < 0 || axis >= kAxes || bytes == nullptr || size != sizeof(Model) ||
        !fuzzy::interval_is_valid(interval) || !conditions_are_valid(conditions)) {
      return Status::kInvalidInput;
    }
    Axis& a = axes_[static_cast<std::size_t>(axis)];
    const std::uint32_t next = a.current.load(std::memory_order_relaxed) == 1 ? 1 : 0;
    Buffer& b = a.buffers[next];
    if (b.readers.load(std::memory_order_acquire) != 0) return Status::kBusy;
    std::memcpy(&b.slot.model, bytes, sizeof(Model));  // the free buffer: nobody reads it
    const fuzzy::ModelProblem found = fuzzy::find_problem(b.slot.model);
    if (problem != nullptr) *problem = found;
    if (found) return Status::kInvalidInput;
    b.interval = interval;
    b.conditions = conditions;
    b.model_id = model_id;
    published_ = true;
    a.current.store(next + 1, std::memory_order_release);
    return Status::kOk;
  }

  /// True when `axis` has a published model. RT-safe.
  bool has_model(int axis) const noexcept {
    if (axis < 0 || axis >= kAxes) return false;
    return axes_[static_cast<std::size_t>(axis)].current.load(std::memory_order_acquire) != kNone;
  }

  /// Id of the model serving `axis` (0 when none or `axis` is out of range). RT-safe.
  std::uint64_t model_id(int axis) const noexcept {
    if (axis < 0 || axis >= kAxes) return 0;
    const Axis& a = axes_[static_cast<std::size_t>(axis)];
    const std::uint32_t current = a.current.load(std::memory_order_acquire);
    return current == kNone ? 0 : a.buffers[current - 1].model_id;
  }

  /// Predicts the dynamic errors of `move` with the model of `move.axis` and fills `out`, as
  /// MoveCompensator::before_approach does (same statuses, same domain rules, same Correction).
  /// RT-safe: no allocation, no lock, no syscall, no loop but the evaluator's fixed ones; callable
  /// from an interrupt handler. `out` is untouched unless ok(status).
  [[nodiscard]] Status before_approach(const MoveRequest& move, Correction& out) const noexcept {
    if (validate_move(move) != Status::kOk || move.axis >= kAxes) return Status::kInvalidInput;
    Axis& a = axes_[move.axis];
    const std::uint32_t current = a.current.load(std::memory_order_acquire);
    if (current == kNone) return Status::kNoModel;
    Buffer& b = a.buffers[current - 1];
    b.readers.fetch_add(1, std::memory_order_acquire);
    typename Model::RawOutput y;
    const Domain d = worse(input_domain(b.slot.model, move), condition_domain(b.conditions, move));
    if (domain_status(Status::kOk, d, outside_domain_) == Status::kOutsideDomainRejected) {
      b.readers.fetch_sub(1, std::memory_order_release);
      return Status::kOutsideDomainRejected;
    }
    const Status s = domain_status(
        fuzzy::evaluate(b.slot.model, Model::input(move), y, outside_domain_), d, outside_domain_);
    const auto u95 = interval_of(b.slot.model, b.interval, move);
    const bool has_interval = b.interval.available();
    const std::uint64_t model_id = b.model_id;
    b.readers.fetch_sub(1, std::memory_order_release);  // the buffer is not read after this
    if (!ok(s)) return s;
    return fill_correction(move, y, u95, has_interval, s, model_id, out);
  }

 private:
  static constexpr std::uint32_t kNone = 0;  ///< `current` before the first publish

  // The model lives in a union whose constructor initialises nothing of it: a default Model is
  // not all zeros (its ranges default to [0, 1]), which would put every buffer in .data. The
  // first publish's copy is a trivial assignment, which starts the member's lifetime.
  union ModelSlot {
    constexpr ModelSlot() noexcept : empty() {}
    char empty;
    Model model;
  };
  static_assert(std::is_trivially_copy_assignable_v<Model> &&
                    std::is_trivially_destructible_v<Model>,
                "ModelSlot relies on a trivial copy into its inactive member");

  struct Buffer {
    ModelSlot slot;
    IntervalCalibration interval{};  ///< published with the model
    Conditions conditions{};         ///< published with the model
    std::uint64_t model_id = 0;
    std::atomic<std::uint32_t> readers{0};  ///< readers inside this buffer now
  };
  struct Axis {
    std::atomic<std::uint32_t> current{kNone};
    std::array<Buffer, 2> buffers{};
  };

  fuzzy::DomainPolicy outside_domain_;
  bool published_ = false;  ///< publisher only: a publish has succeeded (the policy is fixed)
  // mutable: readers count themselves in and out of a buffer through a const compensator.
  mutable std::array<Axis, static_cast<std::size_t>(kAxes)> axes_{};
};

}  // namespace cmmcomp::compensation
