// SPDX-License-Identifier: MIT
/// @file Per-move compensation: one T-S model per axis, hot-swappable, wait-free to evaluate.
///
/// `MoveCompensator::before_approach` predicts MPE, RPE, MAE and RAE of a probing move with the
/// axis' compensation::Model (a 3-set T-S network keyed on its input set: schema.hpp's
/// ServedInputSets, the paper's PV, PD, AV, AD or the same with Y) and returns the touch-point
/// correction +RAE·d. Everything the RT path needs is allocated in the constructor; `publish`
/// copies a model into a preallocated buffer that holds any one of the served models.
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
#include <cmmcomp/compensation/conditions.hpp>
#include <cmmcomp/compensation/move_prediction.hpp>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/schema.hpp>
#include <cmmcomp/status.hpp>
#include <cstdint>
#include <cstdlib>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <type_traits>
#include <variant>

namespace cmmcomp::compensation {

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

/// One model slot per axis serving a model of any of the input sets `Sets` (use MoveCompensator,
/// which serves schema.hpp's ServedInputSets); see the file comment for the hot-swap scheme.
template <typename... Sets>
class BasicMoveCompensator {
  static_assert(sizeof...(Sets) > 0, "a compensator serves at least one input set");

 public:
  /// True when a model of `Inputs` can be published.
  template <typename Inputs>
  static constexpr bool kServes = (std::is_same_v<Inputs, Sets> || ...);

  /// Allocates every model buffer (two per axis, each the size of the largest served model:
  /// about 370 kB for the paper's inputs and the same with Y). Setup only. Throws ConfigError
  /// when `options` is not valid (aborts instead when built with -fno-exceptions).
  explicit BasicMoveCompensator(const CompensatorOptions& options = {})
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
  BasicMoveCompensator(const BasicMoveCompensator&) = delete;
  BasicMoveCompensator& operator=(const BasicMoveCompensator&) = delete;
  ~BasicMoveCompensator() = default;

  /// The options given at construction.
  const CompensatorOptions& options() const noexcept { return options_; }

  /// Validates `model` (fuzzy::validate) and makes it the model of `axis` for every
  /// before_approach call that starts after this returns; calls already running finish with
  /// the model they started with. `model_id` is echoed in every Correction it computes.
  /// Setup only (one publisher at a time; concurrent publishers are serialised by a mutex the
  /// RT path never touches). Waits until no before_approach call still uses the buffer it
  /// retires (bounded by one call's duration unless a reader thread is preempted).
  /// Returns kOk; kInvalidInput (`why` set if given) when `axis` is out of range or the model
  /// is not valid — the model already published keeps serving. A model of any served set
  /// replaces whatever the axis had.
  template <typename Inputs>
  Status publish(int axis,
                 const Model<Inputs, double>& model,
                 std::uint64_t model_id = 0,
                 std::string* why = nullptr) {
    static_assert(kServes<Inputs>, "this compensator does not serve the model's input set");
    return publish_impl(axis, model, IntervalCalibration{}, Conditions{}, model_id, why);
  }

  /// The same, with the model's interval calibration (its file's `uncertainty`): every
  /// Correction it computes carries u95_um. kInvalidInput also when `interval` is not valid
  /// (fuzzy::validate_interval).
  template <typename Inputs>
  Status publish(int axis,
                 const Model<Inputs, double>& model,
                 const IntervalCalibration& interval,
                 std::uint64_t model_id = 0,
                 std::string* why = nullptr) {
    static_assert(kServes<Inputs>, "this compensator does not serve the model's input set");
    return publish_impl(axis, model, interval, Conditions{}, model_id, why);
  }

  /// The same, with the accelerations the model was trained at (its file's `conditions`,
  /// io::compensation_conditions): a move outside them is flagged or refused as
  /// compensation/conditions.hpp says. kInvalidInput also when `conditions` is not valid
  /// (conditions_are_valid).
  template <typename Inputs>
  Status publish(int axis,
                 const Model<Inputs, double>& model,
                 const IntervalCalibration& interval,
                 const Conditions& conditions,
                 std::uint64_t model_id = 0,
                 std::string* why = nullptr) {
    static_assert(kServes<Inputs>, "this compensator does not serve the model's input set");
    return publish_impl(axis, model, interval, conditions, model_id, why);
  }

  /// Number of inputs of the model last published for `axis` (0 when none or bad axis).
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

  /// Predicts the dynamic errors of `move` with the model of `move.axis` (the inputs its set
  /// names, gathered from `move`; outside the training ranges or conditions:
  /// CompensatorOptions::outside_domain and compensation/conditions.hpp) and fills `out`: the
  /// four errors [µm], correction_um = rae_um·direction, flags, model id and the sequence echo.
  /// RT-safe and wait-free: no allocation, no lock, no syscall, two atomic RMWs; never writes
  /// NaN or inf. `out` is untouched unless ok(status).
  /// Returns kOk; kOutsideDomain (an input, PA or AA outside the model's domain, policy kClamp
  /// or kExtrapolate; kFlagOutsideDomain set); kInvalidInput (request fails validate_move, or
  /// the model's result or RAE·d is not finite); kNoModel (nothing published for the axis);
  /// kOutsideDomainRejected (outside with policy kReject, or far outside under any policy).
  [[nodiscard]] Status before_approach(const MoveRequest& move, Correction& out) const noexcept {
    if (validate_move(move) != Status::kOk) return Status::kInvalidInput;
    Axis& a = axes_[move.axis];
    const std::uint64_t entered = a.state.fetch_add(1, std::memory_order_acquire);
    const std::uint64_t index = entered >> kIndexShift;
    if (index == kNone) return Status::kNoModel;
    Buffer& b = a.buffers[static_cast<std::size_t>(index)];
    std::array<double, kModelOutputs> y;
    std::array<double, kModelOutputs> u95;
    const Status s =
        evaluate_served(b.model, b.interval, b.conditions, move, y, u95, options_.outside_domain);
    const std::uint64_t model_id = b.model_id;
    const bool has_interval = b.interval.available();
    b.exits.fetch_add(1, std::memory_order_release);  // the buffer is not read after this
    if (!ok(s)) return s;
    return fill_correction(move, y, u95, has_interval, s, model_id, out);
  }

 private:
  static constexpr unsigned kIndexShift = 62;
  static constexpr std::uint64_t kCountMask = (std::uint64_t{1} << kIndexShift) - 1;
  static constexpr std::uint64_t kNone = 3;  ///< index value: nothing published

  /// One model of any served set, in place (no heap).
  using AnyModel = std::variant<Model<Sets, double>...>;

  /// Evaluates the alternative `model` holds, within its domain (conditions.hpp). No
  /// std::visit: it could throw bad_variant_access, which a variant of trivially copyable
  /// models never needs.
  template <std::size_t kIndex = 0>
  static Status evaluate_served(const AnyModel& model,
                                const IntervalCalibration& interval,
                                const Conditions& conditions,
                                const MoveRequest& move,
                                std::array<double, kModelOutputs>& y,
                                std::array<double, kModelOutputs>& u95,
                                fuzzy::DomainPolicy policy) noexcept {
    if constexpr (kIndex < sizeof...(Sets)) {
      if (const auto* m = std::get_if<kIndex>(&model)) {
        const Domain d = worse(input_domain(*m, move), condition_domain(conditions, move));
        const Status refused = domain_status(Status::kOk, d, policy);
        if (refused == Status::kOutsideDomainRejected) return refused;
        u95 = interval_of(*m, interval, move);
        return domain_status(fuzzy::evaluate(*m, m->input(move), y, policy), d, policy);
      }
      return evaluate_served<kIndex + 1>(model, interval, conditions, move, y, u95, policy);
    } else {
      return Status::kNoModel;  // unreachable: a buffer always holds a served model
    }
  }

  struct Buffer {
    AnyModel model{};
    IntervalCalibration interval{};  ///< published with the model
    Conditions conditions{};         ///< published with the model
    std::uint64_t model_id = 0;
    std::atomic<std::uint64_t> exits{0};  ///< readers that left this buffer
  };
  struct Axis {
    std::atomic<std::uint64_t> state{kNone << kIndexShift};
    std::array<Buffer, 2> buffers{};
    std::atomic<std::uint64_t> published_id{0};  ///< model_id of the last publish
    std::atomic<int> published_inputs{0};        ///< inputs of the last publish (0: none)
  };

  template <typename Inputs>
  Status publish_impl(int axis,
                      const Model<Inputs, double>& model,
                      const IntervalCalibration& interval,
                      const Conditions& conditions,
                      std::uint64_t model_id,
                      std::string* why) {
    if (axis < 0 || axis >= kMaxAxes) {
      if (why != nullptr) *why = "axis out of range";
      return Status::kInvalidInput;
    }
    if (!fuzzy::validate(model, why)) return Status::kInvalidInput;
    if (!fuzzy::validate_interval(interval, why)) return Status::kInvalidInput;
    if (!conditions_are_valid(conditions)) {
      if (why != nullptr) *why = "a PA or AA condition is not a finite range with 0 < lo <= hi";
      return Status::kInvalidInput;
    }
    const std::lock_guard<std::mutex> lock(publish_mutex_);
    Axis& a = axes_[static_cast<std::size_t>(axis)];
    const std::uint64_t old_index = a.state.load(std::memory_order_relaxed) >> kIndexShift;
    // The buffer not current is free: the previous publish waited for its readers to leave.
    const std::uint64_t next = old_index == 0 ? 1 : 0;
    Buffer& b = a.buffers[next];
    b.model.template emplace<Model<Inputs, double>>(model);
    b.interval = interval;
    b.conditions = conditions;
    b.model_id = model_id;
    b.exits.store(0, std::memory_order_relaxed);
    a.published_id.store(model_id, std::memory_order_relaxed);
    a.published_inputs.store(Inputs::kCount, std::memory_order_relaxed);
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

/// The compensator of every input set the project serves (schema.hpp, ServedInputSets).
using MoveCompensator = apply_input_sets<BasicMoveCompensator, ServedInputSets>::type;

}  // namespace cmmcomp::compensation
