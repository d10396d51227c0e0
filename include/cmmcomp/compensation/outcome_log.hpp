// SPDX-License-Identifier: MIT
/// @file The answers a server must not keep to itself: every refused request and every answer
/// outside the model's domain, handed from the request thread to a logger thread.
///
/// `OutcomeLog` is a fixed-capacity single-producer single-consumer ring: the thread that
/// serves requests pushes (wait-free: two atomic loads and one store, no heap, no lock), one
/// other thread pops and writes the log lines (cmmcomp-agent does, rate-limited, and counts
/// what it did not print). When the ring is full the newest event is dropped and counted: the
/// request path never waits for the log.
#pragma once

#include <array>
#include <atomic>
#include <cmmcomp/compensation/move_request.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>

namespace cmmcomp::compensation {

/// One answer worth a log line: the move as the compensator saw it and its status.
struct OutcomeEvent {
  MoveRequest move{};
  Status status = Status::kOk;
};

/// True for the statuses a server logs: every refusal, and kOutsideDomain (answered, but from a
/// model outside the conditions it was trained at).
constexpr bool worth_logging(Status s) noexcept { return s != Status::kOk; }

/// See the file comment. `kCapacity` events fit before the logger must have popped.
template <std::size_t kCapacity = 64>
class OutcomeLog {
  static_assert(kCapacity >= 2 && (kCapacity & (kCapacity - 1)) == 0, "a power of two");

 public:
  /// Producer only. Stores `event`, or counts it as dropped when the ring is full. RT-safe.
  void push(const OutcomeEvent& event) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) >= kCapacity) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return;
    }
    ring_[head & (kCapacity - 1)] = event;
    head_.store(head + 1, std::memory_order_release);
  }

  /// Consumer only. Takes the oldest event into `out`; false when there is none.
  bool pop(OutcomeEvent& out) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    out = ring_[tail & (kCapacity - 1)];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Events dropped because the ring was full. Any thread.
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  std::array<OutcomeEvent, kCapacity> ring_{};
  std::atomic<std::uint64_t> head_{0};  ///< next slot the producer writes
  std::atomic<std::uint64_t> tail_{0};  ///< next slot the consumer reads
  std::atomic<std::uint64_t> dropped_{0};
};

/// The log a server's request handler reports to (CanServerOptions, ModbusServerOptions).
using ServerOutcomeLog = OutcomeLog<>;

}  // namespace cmmcomp::compensation
