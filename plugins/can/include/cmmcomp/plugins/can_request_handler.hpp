// SPDX-License-Identifier: MIT
/// @file The per-frame state machine of the CAN server: reassembles the three parts of a move
/// request, asks the compensator, and produces the response or a reject. No socket and no clock
/// of its own (frames and the time come in as arguments), so it is tested with fake frames.
///
/// Rules (docs/protocol-can.md, "Reassembly"): one request is assembled at a time. Part 0 starts
/// it; part k (1, 2) must follow part k−1 with the same sequence within the part timeout. Every
/// frame that breaks a rule is answered with a reject frame naming the rule; a request is
/// answered only from the three parts of that one request, so a response never carries stale
/// data. A request with WantInterval (protocol version 2) gets the interval (part 3) after the
/// three parts of version 1, from the same compensator call.
#pragma once

#include <array>
#include <atomic>
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>
#include <limits>

namespace cmmcomp::plugins {

/// What a CAN server has seen and done since it started (docs/protocol-can.md, "Counters").
struct CanCounters {
  std::uint64_t frames_in = 0;  ///< request frames received (identifier base + 0)
  std::uint64_t requests = 0;   ///< requests complete (all three parts) and decoded
  std::uint64_t answered = 0;   ///< responses sent (three frames each, four with the interval)
  std::uint64_t intervals = 0;  ///< of those, responses with the interval (part 3, version 2)
  std::uint64_t rejected = 0;   ///< reject frames sent
  /// frames with wrong DLC, unknown part, stray sequence or part, reserved bits
  std::uint64_t malformed = 0;
  std::uint64_t timeouts = 0;      ///< requests abandoned because a part came too late
  std::uint64_t incomplete = 0;    ///< requests abandoned because a new request started
  std::uint64_t out_of_range = 0;  ///< requests with a field, or results, outside their range
  std::uint64_t refused = 0;       ///< requests the compensator refused (invalid, no model, domain)
  /// requests answered OK but flagged outside the model's domain (an input, PA or AA outside
  /// its training conditions: docs/compensator.md, "Domain")
  std::uint64_t outside_domain = 0;
  std::uint64_t heartbeats = 0;   ///< heartbeats sent (five frames each)
  std::uint64_t send_errors = 0;  ///< frames the socket did not take
  std::uint64_t ignored = 0;      ///< frames with other identifiers (0 while the filter works)
};

/// The frames one call produces: at most two rejects (a timeout, then the frame's own), or the
/// three or four frames of one response (an expired request cannot be answered, so a response
/// never follows a reject in one call).
struct CanFrameBatch {
  static constexpr std::size_t kCapacity = 4;
  static_assert(kCapacity >= can::kResponseParts + 1, "a response with its interval part");
  std::array<can::Frame, kCapacity> frames{};
  std::size_t size = 0;

  /// Appends `f`; a full batch drops it (cannot happen with the handler's bounds). RT-safe.
  void push(const can::Frame& f) noexcept {
    if (size < kCapacity) frames[size++] = f;
  }
};

/// Reassembles requests and answers them (see the file comment). Single-threaded: one thread
/// calls on_frame/on_time; counters() may be read from any thread.
class CanRequestHandler {
 public:
  /// `compensator` must outlive the handler. `part_timeout` > 0 is the longest gap allowed
  /// between two parts of a request. Setup only.
  CanRequestHandler(const compensation::MoveCompensator& compensator,
                    std::uint32_t base_id,
                    std::chrono::nanoseconds part_timeout) noexcept
      : compensator_(compensator), base_id_(base_id), part_timeout_ns_(part_timeout.count()) {}

  /// Every refused request and every outside-domain answer is pushed to `log` (may be null:
  /// none), which must outlive the handler. Setup only, before the first frame.
  void set_outcome_log(compensation::ServerOutcomeLog* log) noexcept { outcome_log_ = log; }

  /// Handles one received frame at time `now_ns` (any monotonic clock, ns) and appends the
  /// frames to send to `out`. Frames with another identifier are counted as ignored. RT-safe:
  /// no allocation, no exception, no syscall, bounded (one compensator call at most).
  void on_frame(const can::Frame& f, std::int64_t now_ns, CanFrameBatch& out) noexcept {
    if (f.id != base_id_ + can::kRequestOffset) {
      bump(counters_.ignored);
      return;
    }
    bump(counters_.frames_in);
    on_time(now_ns, out);  // a part that comes after the deadline finds the request expired
    const std::uint64_t w = can::load_word(f);
    const bool readable = f.dlc >= 1;
    const auto part = static_cast<std::uint8_t>(can::get_raw(w, can::request::kPart));
    const auto sequence = static_cast<std::uint8_t>(can::get_raw(w, can::request::kSequence));
    if (f.dlc != can::kFrameDlc) {
      malformed(can::RejectReason::kWrongDlc, readable, sequence, part, out);
      return;
    }
    if (part >= can::kRequestParts) {
      malformed(can::RejectReason::kUnknownPart, true, sequence, part, out);
      return;
    }
    if (part == 0) {
      if (assembling_) {
        bump(counters_.incomplete);
        reject(can::RejectReason::kIncomplete, sequence_, next_part_, 0, 0, out);
      }
      assembling_ = true;
      sequence_ = sequence;
      words_[0] = w;
      next_part_ = 1;
      deadline_ns_ = deadline_after(now_ns);
      return;
    }
    if (!assembling_) {
      malformed(can::RejectReason::kMissingPart, true, sequence, part, out, false);
      return;
    }
    if (sequence != sequence_) {  // a stray part of another request; the current one goes on
      malformed(can::RejectReason::kSequenceMismatch, true, sequence, part, out, false);
      return;
    }
    if (part != next_part_) {  // a duplicate or a skipped part: the request cannot be trusted
      malformed(can::RejectReason::kMissingPart, true, sequence, part, out);
      return;
    }
    words_[part] = w;
    if (part + 1 < can::kRequestParts) {
      next_part_ = static_cast<std::uint8_t>(part + 1);
      deadline_ns_ = deadline_after(now_ns);
      return;
    }
    assembling_ = false;
    answer(out);
  }

  /// Expires a request whose next part is overdue at `now_ns` (reject kTimeout). Call it when
  /// the deadline passes without a frame. RT-safe.
  void on_time(std::int64_t now_ns, CanFrameBatch& out) noexcept {
    if (assembling_ && now_ns >= deadline_ns_) {
      assembling_ = false;
      bump(counters_.timeouts);
      reject(can::RejectReason::kTimeout, sequence_, next_part_, 0, 0, out);
    }
  }

  /// True while a request is incomplete; deadline_ns() is then when it expires. RT-safe.
  bool assembling() const noexcept { return assembling_; }
  std::int64_t deadline_ns() const noexcept { return deadline_ns_; }

  /// A snapshot of the counters (each counter exact; not one instant across counters). Any
  /// thread. RT-safe.
  CanCounters counters() const noexcept {
    CanCounters c;
    c.frames_in = counters_.frames_in.load(std::memory_order_relaxed);
    c.requests = counters_.requests.load(std::memory_order_relaxed);
    c.answered = counters_.answered.load(std::memory_order_relaxed);
    c.intervals = counters_.intervals.load(std::memory_order_relaxed);
    c.rejected = counters_.rejected.load(std::memory_order_relaxed);
    c.malformed = counters_.malformed.load(std::memory_order_relaxed);
    c.timeouts = counters_.timeouts.load(std::memory_order_relaxed);
    c.incomplete = counters_.incomplete.load(std::memory_order_relaxed);
    c.out_of_range = counters_.out_of_range.load(std::memory_order_relaxed);
    c.refused = counters_.refused.load(std::memory_order_relaxed);
    c.outside_domain = counters_.outside_domain.load(std::memory_order_relaxed);
    c.heartbeats = counters_.heartbeats.load(std::memory_order_relaxed);
    c.send_errors = counters_.send_errors.load(std::memory_order_relaxed);
    c.ignored = counters_.ignored.load(std::memory_order_relaxed);
    return c;
  }

  /// The heartbeat as of now (tick = heartbeats sent so far) and counts it. RT-safe.
  can::HeartbeatInfo next_heartbeat() noexcept {
    can::HeartbeatInfo h;
    h.tick = static_cast<std::uint8_t>(counters_.heartbeats.load(std::memory_order_relaxed) & 0x1F);
    h.requests = static_cast<std::uint16_t>(counters_.requests.load(std::memory_order_relaxed));
    h.answered = static_cast<std::uint16_t>(counters_.answered.load(std::memory_order_relaxed));
    h.rejected = static_cast<std::uint16_t>(counters_.rejected.load(std::memory_order_relaxed));
    for (int a = 0; a < compensation::kMaxAxes; ++a) {
      const auto u = static_cast<std::size_t>(a);
      if (compensator_.has_model(a))
        h.model_mask = static_cast<std::uint8_t>(h.model_mask | (1u << u));
      h.model_ids[u] = compensator_.model_id(a);
    }
    bump(counters_.heartbeats);
    return h;
  }

  /// Counts `n` frames the socket refused. RT-safe.
  void count_send_errors(std::uint64_t n) noexcept {
    counters_.send_errors.fetch_add(n, std::memory_order_relaxed);
  }

 private:
  struct AtomicCounters {
    std::atomic<std::uint64_t> frames_in{0}, requests{0}, answered{0}, intervals{0}, rejected{0},
        malformed{0}, timeouts{0}, incomplete{0}, out_of_range{0}, refused{0}, outside_domain{0},
        heartbeats{0}, send_errors{0}, ignored{0};
  };

  /// now_ns + the part timeout, saturated: a clock near the end of int64 (any monotonic clock
  /// is allowed) must not wrap the deadline into the past and reject a request that is on time.
  std::int64_t deadline_after(std::int64_t now_ns) const noexcept {
    const std::int64_t room = std::numeric_limits<std::int64_t>::max() - part_timeout_ns_;
    return now_ns > room ? std::numeric_limits<std::int64_t>::max() : now_ns + part_timeout_ns_;
  }

  // One writer thread: a load and a store are enough, and cheaper than a locked add.
  static void bump(std::atomic<std::uint64_t>& c) noexcept {
    c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }

  void reject(can::RejectReason reason,
              std::uint8_t sequence,
              std::uint8_t part,
              std::uint8_t detail,
              std::int16_t status,
              CanFrameBatch& out) noexcept {
    bump(counters_.rejected);
    can::RejectInfo r;
    r.reason = reason;
    r.sequence = sequence;
    r.part = part;
    r.detail = detail;
    r.status = status;
    r.rejected = static_cast<std::uint16_t>(counters_.rejected.load(std::memory_order_relaxed));
    out.push(can::encode_reject(r, base_id_));
  }

  /// Rejects a frame that breaks a framing rule. With `abandons`, a request being assembled is
  /// dropped too when the frame may belong to it (same sequence, or the sequence unreadable).
  void malformed(can::RejectReason reason,
                 bool readable,
                 std::uint8_t sequence,
                 std::uint8_t part,
                 CanFrameBatch& out,
                 bool abandons = true) noexcept {
    bump(counters_.malformed);
    if (abandons && assembling_ && (!readable || sequence == sequence_)) assembling_ = false;
    reject(reason, readable ? sequence : can::kUnknown, readable ? part : can::kUnknown, 0, 0, out);
  }

  void answer(CanFrameBatch& out) noexcept {
    bump(counters_.requests);
    compensation::MoveRequest move;
    const can::RequestCheck check = can::decode_request(words_, sequence_, move);
    if (check.reason != can::RejectReason::kNone) {
      if (check.reason == can::RejectReason::kFieldOutOfRange) {
        bump(counters_.out_of_range);
      } else {
        bump(counters_.malformed);
      }
      reject(check.reason, sequence_, check.part, static_cast<std::uint8_t>(check.field), 0, out);
      return;
    }
    compensation::Correction c;
    const Status s = compensator_.before_approach(move, c);
    if (outcome_log_ != nullptr && compensation::worth_logging(s)) outcome_log_->push({move, s});
    if (s == Status::kOutsideDomain) bump(counters_.outside_domain);
    if (!ok(s)) {
      bump(counters_.refused);
      reject(can::reject_reason(s), sequence_, can::kUnknown, 0, static_cast<std::int16_t>(s), out);
      return;
    }
    can::ResponseFrames frames;
    can::Frame interval;
    can::ResponseField bad = can::ResponseField::kNone;
    if (can::encode_response(c, move.axis, base_id_, frames, &bad) != Status::kOk ||
        (check.want_interval && can::encode_interval(c, base_id_, interval, &bad) != Status::kOk)) {
      bump(counters_.out_of_range);
      reject(can::RejectReason::kResultOutOfRange,
             sequence_,
             can::kUnknown,
             static_cast<std::uint8_t>(bad),
             static_cast<std::int16_t>(s),
             out);
      return;
    }
    for (const can::Frame& f : frames) out.push(f);
    if (check.want_interval) {
      out.push(interval);
      bump(counters_.intervals);
    }
    bump(counters_.answered);
  }

  const compensation::MoveCompensator& compensator_;
  compensation::ServerOutcomeLog* outcome_log_ = nullptr;
  std::uint32_t base_id_;
  std::int64_t part_timeout_ns_;
  bool assembling_ = false;
  std::uint8_t sequence_ = 0;
  std::uint8_t next_part_ = 0;
  std::int64_t deadline_ns_ = 0;
  std::array<std::uint64_t, can::kRequestParts> words_{};
  AtomicCounters counters_;
};

}  // namespace cmmcomp::plugins
