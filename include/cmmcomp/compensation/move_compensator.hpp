// SPDX-License-Identifier: MIT
/// @file Per-move compensation: one T-S model per axis, hot-swappable, wait-free to evaluate.
///
/// `MoveCompensator::before_approach` predicts MPE, RPE, MAE and RAE of a probing move with the
/// paper's 4-input, 3-set network (fuzzy::PaperMultiNetwork, outputs in that order) and returns
/// the touch-point correction +RAE·d. Everything the RT path needs is allocated in the
/// constructor; `publish` copies a model into a preallocated buffer.
///
/// Hot swap (docs/compensator.md, "Threading"): each axis has two model buffers and one atomic
/// 64-bit word `state` = (current buffer index << 62) | entries, where `entries` counts the
/// readers that entered through this value of the word. A reader does one fetch_add on
/// `state` (learning the buffer and announcing itself in one step), evaluates, and does one
/// fetch_add on that buffer's `exits` counter: wait-free, two atomic RMWs, no loop. The writer
/// fills the other buffer, exchanges `state` (getting the entry count of the old buffer) and
/// then waits ON ITS SIDE until the old buffer's `exits` reaches that count; only then may the
/// old buffer be overwritten by a later publish. A buffer a reader may still use is therefore
/// never written. 62 counter bits overflow after 4.6·10¹⁸ calls between two publications.
#pragma once

#include <array>
#include <atomic>
#include <cmmcomp/compensation/move_prediction.hpp>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/error.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>

namespace cmmcomp::compensation {

/// The paper's model a MoveCompensator evaluates: inputs (PV [mm/s], PD [mm], AV [mm/s],
/// AD [mm]), 3 sets each, 81 rules, outputs (MPE, RPE, MAE, RAE) [µm] — what cmmcomp-train
/// writes by default.
using CompensationModel = fuzzy::PaperMultiNetwork;
/// The same with the carriage position as a fifth input (PV, PD, AV, AD, Y [mm]; 243 rules):
/// the dynamic errors grow with Y (the paper's Table 2), which the 4-input model cannot see.
/// `cmmcomp-train fit --inputs pv,pd,av,ad,y` writes it.
using CompensationModelY = fuzzy::TskModel<double, 5, 3, 4>;

/// Options of a MoveCompensator, fixed at construction.
struct CompensatorOptions {
  /// What to do with a move outside the model's training ranges. Default kClamp: clamp the
  /// inputs, compute, set kFlagOutsideDomain and return Status::kOutsideDomain.
  fuzzy::DomainPolicy outside_domain = fuzzy::DomainPolicy::kClamp;

  /// True when every field is usable; otherwise false and, if `why` is given, the reason.
  /// Setup only.
  bool is_valid(std::string* why = nullptr) const {
    if (outside_domain != fuzzy::DomainPolicy::kClamp &&
        outside_domain != fuzzy::DomainPolicy::kExtrapolate &&
        outside_domain != fuzzy::DomainPolicy::kReject) {
      if (why != nullptr) *why = "outside_domain is not a DomainPolicy value";
      return false;
    }
    return true;
  }
};

/// One model slot per axis; see the file comment for the hot-swap scheme.
class MoveCompensator {
 public:
  using Model = CompensationModel;

  /// Allocates every model buffer (about 480 kB: two 4-input and two 5-input models per axis).
  /// Setup only. Throws ConfigError when `options` is not valid (aborts instead when built
  /// with -fno-exceptions).
  explicit MoveCompensator(const CompensatorOptions& options = {})
      : options_(options), axes_(std::make_unique<Axis[]>(kMaxAxes)) {
    std::string why;
    if (!options_.is_valid(&why)) {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
      throw ConfigError("CompensatorOptions: " + why);
#else
      std::abort();
#endif
    }
  }
  MoveCompensator(const MoveCompensator&) = delete;
  MoveCompensator& operator=(const MoveCompensator&) = delete;
  ~MoveCompensator() = default;

  /// The options given at construction.
  const CompensatorOptions& options() const noexcept { return options_; }

  /// Validates `model` (fuzzy::validate) and makes it the model of `axis` for every
  /// before_approach call that starts after this returns; calls already running finish with
  /// the model they started with. `model_id` is echoed in every Correction it computes.
  /// Setup only (one publisher at a time; concurrent publishers are serialised by a mutex the
  /// RT path never touches). Waits until no before_approach call still uses the buffer it
  /// retires (bounded by one call's duration unless a reader thread is preempted).
  /// Returns kOk; kInvalidInput (`why` set if given) when `axis` is out of range or the model
  /// is not valid — the model already published keeps serving.
  Status publish(int axis,
                 const Model& model,
                 std::uint64_t model_id = 0,
                 std::string* why = nullptr) {
    return publish_impl(axis, model, model_id, why);
  }
  /// The same for a model with Y as fifth input; it replaces whatever the axis had.
  Status publish(int axis,
                 const CompensationModelY& model,
                 std::uint64_t model_id = 0,
                 std::string* why = nullptr) {
    return publish_impl(axis, model, model_id, why);
  }

  /// Inputs of the model last published for `axis`: 4, 5, or 0 when none (or bad axis).
  /// RT-safe.
  int model_inputs(int axis) const noexcept {
    if (axis < 0 || axis >= kMaxAxes) return 0;
    return axes_[static_cast<std::size_t>(axis)].published_inputs.load(std::memory_order_relaxed);
  }

  /// True when `axis` has a published model. Not for decisions on the RT path (it may change
  /// right after); use the Status of before_approach. RT-safe.
  bool has_model(int axis) const noexcept {
    if (axis < 0 || axis >= kMaxAxes) return false;
    return (axes_[static_cast<std::size_t>(axis)].state.load(std::memory_order_acquire) >>
            kIndexShift) != kNone;
  }

  /// Id of the model last published for `axis` (0 when none or `axis` is out of range), for
  /// status and heartbeat reports. A before_approach call that overlaps a publish may still
  /// answer with the previous model; its Correction::model_id says which. RT-safe.
  std::uint64_t model_id(int axis) const noexcept {
    if (axis < 0 || axis >= kMaxAxes) return 0;
    return axes_[static_cast<std::size_t>(axis)].published_id.load(std::memory_order_relaxed);
  }

  /// Predicts the dynamic errors of `move` with the model of `move.axis` (a 5-input model also
  /// reads move.y_mm; outside the training ranges: CompensatorOptions::outside_domain) and
  /// fills `out`: the four errors [µm],
  /// correction_um = rae_um·direction, flags, model id and the sequence echo.
  /// RT-safe and wait-free: no allocation, no lock, no syscall, two atomic RMWs; never writes
  /// NaN or inf. `out` is untouched unless ok(status).
  /// Returns kOk; kOutsideDomain (policy kClamp or kExtrapolate; kFlagOutsideDomain set);
  /// kInvalidInput (request fails validate_move, or the model's result or RAE·d is not finite);
  /// kNoModel (nothing published for the axis); kOutsideDomainRejected (policy kReject).
  [[nodiscard]] Status before_approach(const MoveRequest& move, Correction& out) const noexcept {
    if (validate_move(move) != Status::kOk) return Status::kInvalidInput;
    Axis& a = axes_[move.axis];
    const std::uint64_t entered = a.state.fetch_add(1, std::memory_order_acquire);
    const std::uint64_t index = entered >> kIndexShift;
    if (index == kNone) return Status::kNoModel;
    Buffer& b = a.buffers[static_cast<std::size_t>(index)];
    Model::RawOutput y;
    const Status s =
        b.inputs == 5
            ? fuzzy::evaluate(
                  b.model_y, model_input<CompensationModelY>(move), y, options_.outside_domain)
            : fuzzy::evaluate(b.model, model_input<Model>(move), y, options_.outside_domain);
    const std::uint64_t model_id = b.model_id;
    b.exits.fetch_add(1, std::memory_order_release);  // the buffer is not read after this
    if (!ok(s)) return s;
    return fill_correction(move, y, s, model_id, out);
  }

 private:
  static constexpr unsigned kIndexShift = 62;
  static constexpr std::uint64_t kCountMask = (std::uint64_t{1} << kIndexShift) - 1;
  static constexpr std::uint64_t kNone = 3;  ///< index value: nothing published

  struct Buffer {
    int inputs = 4;                ///< which of the two models below is valid
    Model model{};                 ///< inputs == 4
    CompensationModelY model_y{};  ///< inputs == 5
    std::uint64_t model_id = 0;
    std::atomic<std::uint64_t> exits{0};  ///< readers that left this buffer
  };
  struct Axis {
    std::atomic<std::uint64_t> state{kNone << kIndexShift};
    std::array<Buffer, 2> buffers{};
    std::atomic<std::uint64_t> published_id{0};  ///< model_id of the last publish
    std::atomic<int> published_inputs{0};        ///< inputs of the last publish (0: none)
  };

  template <typename AnyModel>
  Status publish_impl(int axis, const AnyModel& model, std::uint64_t model_id, std::string* why) {
    if (axis < 0 || axis >= kMaxAxes) {
      if (why != nullptr) *why = "axis out of range";
      return Status::kInvalidInput;
    }
    if (!fuzzy::validate(model, why)) return Status::kInvalidInput;
    const std::lock_guard<std::mutex> lock(publish_mutex_);
    Axis& a = axes_[static_cast<std::size_t>(axis)];
    const std::uint64_t old_index = a.state.load(std::memory_order_relaxed) >> kIndexShift;
    // The buffer not current is free: the previous publish waited for its readers to leave.
    const std::uint64_t next = old_index == 0 ? 1 : 0;
    Buffer& b = a.buffers[next];
    if constexpr (std::is_same_v<AnyModel, CompensationModelY>) {
      b.model_y = model;
      b.inputs = 5;
    } else {
      b.model = model;
      b.inputs = 4;
    }
    b.model_id = model_id;
    b.exits.store(0, std::memory_order_relaxed);
    a.published_id.store(model_id, std::memory_order_relaxed);
    a.published_inputs.store(b.inputs, std::memory_order_relaxed);
    const std::uint64_t old = a.state.exchange(next << kIndexShift, std::memory_order_acq_rel);
    const std::uint64_t entered = old & kCountMask;
    if ((old >> kIndexShift) != kNone) {
      const Buffer& retired = a.buffers[static_cast<std::size_t>(old >> kIndexShift)];
      while ((retired.exits.load(std::memory_order_acquire) & kCountMask) != entered) {
        std::this_thread::yield();
      }
    }
    return Status::kOk;
  }

  CompensatorOptions options_;
  std::unique_ptr<Axis[]> axes_;  // mutable through the pointer: readers count on atomics
  std::mutex publish_mutex_;
};

}  // namespace cmmcomp::compensation
