// SPDX-License-Identifier: MIT
/// @file The per-request path of the Modbus server: one request PDU in, a decision out, the
/// register images updated — no sockets, no libmodbus, no allocation (RT-safe).
///
/// ModbusServer receives a frame with libmodbus, passes its PDU here and then lets libmodbus
/// answer from the images this class owns (modbus_reply on a modbus_mapping_t that points at
/// them), or answers with the exception this class chose. Every check that can refuse a request
/// happens here, before libmodbus touches the images, so a refused write changes nothing.
///
/// Whole results: a triggering write computes into a staging copy of the result block and
/// copies it into the served image only when the computation is complete. The server calls
/// `handle` and modbus_reply from its one thread, so no reply can be built between the two.
#pragma once

#include <atomic>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/outcome_log.hpp>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/status.hpp>
#include <cstddef>
#include <cstdint>

namespace cmmcomp::plugins {

/// What the server does counted since it started (ModbusServer::counters()).
struct ModbusCounters {
  std::uint64_t requests = 0;      ///< request frames addressed to this server
  std::uint64_t answered = 0;      ///< normal (non-exception) replies decided
  std::uint64_t rejected = 0;      ///< requests refused for a bad value (exception 03)
  std::uint64_t exceptions = 0;    ///< exception replies of any code (01, 02, 03, 0B)
  std::uint64_t computations = 0;  ///< triggering writes that produced a result
  std::uint64_t refused = 0;  ///< of those, results the compensator refused (status in the block)
  std::uint64_t outside_domain = 0;     ///< of those, OK results flagged outside the model's domain
  std::uint64_t clients_connected = 0;  ///< TCP connections accepted (RTU: 0)
  std::uint64_t clients_active = 0;     ///< TCP connections open now
  std::uint64_t clients_refused = 0;    ///< TCP connections closed at once: max_tcp_clients open
  std::uint64_t receive_errors = 0;     ///< frames lost: bad CRC or MBAP header, truncated,
                                        ///< timed out, peer gone mid-frame
  std::uint64_t clients_idle_closed = 0;  ///< TCP connections closed after idle_timeout_ms
  std::uint64_t clients_evicted = 0;      ///< TCP connections closed for a new one (evict_idle_ms)
};

/// Modbus function codes the server implements.
enum ModbusFunction : std::uint8_t {
  kReadHoldingRegisters = 0x03,
  kReadInputRegisters = 0x04,
  kWriteSingleRegister = 0x06,
  kWriteMultipleRegisters = 0x10,
  kReadWriteMultipleRegisters = 0x17,
};

/// Modbus exception codes the server answers with.
enum ModbusException : std::uint8_t {
  kIllegalFunction = 0x01,
  kIllegalDataAddress = 0x02,
  kIllegalDataValue = 0x03,
  kGatewayTargetFailed = 0x0B,
};

/// What to send back for one request.
struct ModbusDecision {
  enum class Kind : std::uint8_t {
    kReply,      ///< answer normally from the register images (modbus_reply)
    kException,  ///< answer with `exception` (modbus_reply_exception)
    kSilent,     ///< send nothing (RTU: another unit's or a broadcast frame)
  };
  Kind kind = Kind::kReply;
  std::uint8_t exception = 0;  ///< ModbusException when kind == kException
};

/// Transport the request came over; decides how a foreign unit id is treated.
enum class ModbusTransport : std::uint8_t {
  kTcp,  ///< unit id = configured or 0xFF served; others: exception 0B (gateway target failed)
  kRtu,  ///< unit id = configured served; others and broadcast (0) ignored
};

/// The register images and the request logic of one server. Not thread-safe except
/// `counters()`, which any thread may call.
class ModbusRequestHandler {
 public:
  /// `compensator` must outlive the handler; its models may be republished at any time.
  /// Setup only (never allocates).
  ModbusRequestHandler(const compensation::MoveCompensator& compensator,
                       std::uint8_t unit_id,
                       ModbusTransport transport) noexcept
      : compensator_(compensator), unit_id_(unit_id), transport_(transport) {
    holding_.fill(0);
    input_.fill(0);
    input_[modbus::kProtocolVersionReg] = modbus::kProtocolVersion;
  }
  /// Every refused request and every outside-domain answer is pushed to `log` (may be null:
  /// none), which must outlive the handler. Setup only, before the first request.
  void set_outcome_log(compensation::ServerOutcomeLog* log) noexcept { outcome_log_ = log; }

  ModbusRequestHandler(const ModbusRequestHandler&) = delete;
  ModbusRequestHandler& operator=(const ModbusRequestHandler&) = delete;

  /// Decides the answer to one request and applies it to the images: `unit` is the frame's unit
  /// id (slave address), `pdu` the function code and its data (no MBAP header, no CRC). A valid
  /// write is applied (and, when it covers the sequence register, the move is computed and the
  /// result block replaced as a whole) before this returns; a refused request changes no
  /// register. Before a read of input registers the status block (counters, model ids) is
  /// refreshed. RT-safe: no allocation, no lock, no syscall; bounded work.
  ModbusDecision handle(std::uint8_t unit, const std::uint8_t* pdu, std::size_t size) noexcept {
    // Codes 0x80..0xFF are exception responses, never requests, and their own exception answer
    // (code | 0x80) cannot be encoded: libmodbus would send 0x90 as 0x10, which reads as a
    // normal FC16 answer. Such a frame is not answered, whatever unit it is for (issue 16 D11).
    if (pdu != nullptr && size >= 1 && pdu[0] >= 0x80) {
      if (addressed_to_me(unit)) bump(requests_);
      return {ModbusDecision::Kind::kSilent, 0};
    }
    if (!addressed_to_me(unit)) {
      if (transport_ == ModbusTransport::kRtu) return {ModbusDecision::Kind::kSilent, 0};
      bump(requests_);
      return exception(kGatewayTargetFailed);
    }
    bump(requests_);
    if (pdu == nullptr || size < 1) return exception(kIllegalDataValue);
    const std::uint8_t function = pdu[0];
    switch (function) {
      case kReadHoldingRegisters:
      case kReadInputRegisters: {
        if (size != 5) return exception(kIllegalDataValue);
        const std::uint16_t address = be16(pdu + 1);
        const std::uint16_t count = be16(pdu + 3);
        const std::size_t limit =
            function == kReadHoldingRegisters ? modbus::kHoldingCount : modbus::kInputCount;
        if (count < 1 || count > 125) return exception(kIllegalDataValue);
        if (std::size_t{address} + count > limit) return exception(kIllegalDataAddress);
        if (function == kReadInputRegisters) refresh_status();
        return reply();
      }
      case kWriteSingleRegister: {
        if (size != 5) return exception(kIllegalDataValue);
        return write(be16(pdu + 1), 1, pdu + 3);
      }
      case kWriteMultipleRegisters: {
        if (size < 6) return exception(kIllegalDataValue);
        const std::uint16_t count = be16(pdu + 3);
        if (count < 1 || count > 123 || pdu[5] != 2 * count || size != 6 + 2u * count) {
          return exception(kIllegalDataValue);
        }
        return write(be16(pdu + 1), count, pdu + 6);
      }
      case kReadWriteMultipleRegisters: {
        if (size < 10) return exception(kIllegalDataValue);
        const std::uint16_t read_address = be16(pdu + 1);
        const std::uint16_t read_count = be16(pdu + 3);
        const std::uint16_t write_count = be16(pdu + 7);
        if (read_count < 1 || read_count > 125 || write_count < 1 || write_count > 121 ||
            pdu[9] != 2 * write_count || size != 10 + 2u * write_count) {
          return exception(kIllegalDataValue);
        }
        if (std::size_t{read_address} + read_count > modbus::kHoldingCount) {
          return exception(kIllegalDataAddress);
        }
        return write(be16(pdu + 5), write_count, pdu + 10);  // the read follows the write
      }
      default:
        return exception(kIllegalFunction);
    }
  }

  /// The holding-register image (the request); libmodbus reads and writes it through
  /// modbus_mapping_t::tab_registers, only from the server thread.
  modbus::HoldingRegisters& holding() noexcept { return holding_; }
  const modbus::HoldingRegisters& holding() const noexcept { return holding_; }
  /// The input-register image (result and status); modbus_mapping_t::tab_input_registers.
  modbus::InputRegisters& input() noexcept { return input_; }
  const modbus::InputRegisters& input() const noexcept { return input_; }

  /// The server reports what happens outside `handle`. RT-safe.
  void note_client_connected() noexcept {
    bump(clients_connected_);
    bump(clients_active_);
  }
  void note_client_closed() noexcept {
    clients_active_.store(clients_active_.load(std::memory_order_relaxed) - 1,
                          std::memory_order_relaxed);
  }
  void note_client_refused() noexcept { bump(clients_refused_); }
  void note_receive_error() noexcept { bump(receive_errors_); }
  void note_client_idle_closed() noexcept { bump(clients_idle_closed_); }
  void note_client_evicted() noexcept { bump(clients_evicted_); }
  /// A reply `handle` decided could not be sent (peer gone): it does not count as answered.
  void note_reply_failed() noexcept {
    answered_.store(answered_.load(std::memory_order_relaxed) - 1, std::memory_order_relaxed);
  }

  /// A snapshot of the counters (each value exact; the set not taken atomically). Any thread.
  ModbusCounters counters() const noexcept {
    ModbusCounters c;
    c.requests = requests_.load(std::memory_order_relaxed);
    c.answered = answered_.load(std::memory_order_relaxed);
    c.refused = refused_.load(std::memory_order_relaxed);
    c.outside_domain = outside_domain_.load(std::memory_order_relaxed);
    c.rejected = rejected_.load(std::memory_order_relaxed);
    c.exceptions = exceptions_.load(std::memory_order_relaxed);
    c.computations = computations_.load(std::memory_order_relaxed);
    c.clients_connected = clients_connected_.load(std::memory_order_relaxed);
    c.clients_active = clients_active_.load(std::memory_order_relaxed);
    c.clients_refused = clients_refused_.load(std::memory_order_relaxed);
    c.receive_errors = receive_errors_.load(std::memory_order_relaxed);
    c.clients_idle_closed = clients_idle_closed_.load(std::memory_order_relaxed);
    c.clients_evicted = clients_evicted_.load(std::memory_order_relaxed);
    return c;
  }

 private:
  using Counter = std::atomic<std::uint64_t>;

  // One writer (the server thread): load + store is enough and cheaper than a locked RMW.
  static void bump(Counter& c) noexcept {
    c.store(c.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  }
  static std::uint16_t be16(const std::uint8_t* p) noexcept {
    return static_cast<std::uint16_t>((p[0] << 8) | p[1]);
  }

  bool addressed_to_me(std::uint8_t unit) const noexcept {
    if (unit == unit_id_) return true;
    return transport_ == ModbusTransport::kTcp && unit == 0xFF;
  }

  ModbusDecision reply() noexcept {
    bump(answered_);
    return {ModbusDecision::Kind::kReply, 0};
  }
  ModbusDecision exception(std::uint8_t code) noexcept {
    bump(exceptions_);
    if (code == kIllegalDataValue) bump(rejected_);
    return {ModbusDecision::Kind::kException, code};
  }

  /// Applies `count` registers from big-endian `data` at `address` if every touched field stays
  /// valid and, when the sequence register is written, the whole request is valid; computes.
  ModbusDecision write(std::uint16_t address,
                       std::uint16_t count,
                       const std::uint8_t* data) noexcept {
    if (std::size_t{address} + count > modbus::kRequestCount) {  // the copy is read-only
      return exception(kIllegalDataAddress);
    }
    modbus::HoldingRegisters merged = holding_;
    for (std::uint16_t i = 0; i < count; ++i) {
      merged[static_cast<std::size_t>(address + i)] = be16(data + std::ptrdiff_t{2} * i);
    }
    for (std::uint16_t i = 0; i < count; ++i) {
      if (modbus::check_field(merged, static_cast<std::uint16_t>(address + i)) != Status::kOk) {
        return exception(kIllegalDataValue);
      }
    }
    const bool trigger = address + count > modbus::kSequence;
    if (!trigger) {
      holding_ = merged;
      return reply();
    }
    compensation::MoveRequest request;
    if (modbus::decode_request(merged, request) != Status::kOk ||
        compensation::validate_move(request) != Status::kOk) {
      return exception(kIllegalDataValue);
    }
    compensation::Correction correction;
    const Status status = compensator_.before_approach(request, correction);
    if (outcome_log_ != nullptr && compensation::worth_logging(status)) {
      outcome_log_->push({request, status});
    }
    if (!ok(status)) bump(refused_);
    if (status == Status::kOutsideDomain) bump(outside_domain_);
    // Staging: the result block is built completely, then replaces the served one in one copy.
    modbus::InputRegisters staged = input_;
    modbus::encode_result(
        merged[modbus::kSequence], merged[modbus::kAxis], status, correction, staged);
    holding_ = merged;
    for (std::size_t r = 0; r < modbus::kResultWords; ++r) {
      const std::uint16_t v = staged[modbus::kResultSequence + r];
      input_[modbus::kResultSequence + r] = v;
      holding_[modbus::kResultCopy + r] = v;
    }
    for (std::size_t r = 0; r < modbus::kIntervalWords; ++r) {
      const std::uint16_t v = staged[modbus::kIntervalFlags + r];
      input_[modbus::kIntervalFlags + r] = v;
      holding_[modbus::kIntervalCopy + r] = v;
    }
    bump(computations_);
    return reply();
  }

  /// Copies the counters (low 32 bits) and the current model id of every axis into the status
  /// block, so a read shows them as of this request.
  void refresh_status() noexcept {
    using namespace modbus;
    put_u32(&input_[kRequests],
            static_cast<std::uint32_t>(requests_.load(std::memory_order_relaxed)));
    put_u32(&input_[kAnswered],
            static_cast<std::uint32_t>(answered_.load(std::memory_order_relaxed)));
    put_u32(&input_[kRejected],
            static_cast<std::uint32_t>(rejected_.load(std::memory_order_relaxed)));
    put_u32(&input_[kExceptions],
            static_cast<std::uint32_t>(exceptions_.load(std::memory_order_relaxed)));
    put_u32(&input_[kComputations],
            static_cast<std::uint32_t>(computations_.load(std::memory_order_relaxed)));
    put_u32(&input_[kClientsConnected],
            static_cast<std::uint32_t>(clients_connected_.load(std::memory_order_relaxed)));
    for (int axis = 0; axis < compensation::kMaxAxes; ++axis) {
      put_u64(&input_[static_cast<std::size_t>(kModelIdAxis0) +
                      std::size_t{4} * static_cast<std::size_t>(axis)],
              compensator_.model_id(axis));
    }
  }

  const compensation::MoveCompensator& compensator_;
  compensation::ServerOutcomeLog* outcome_log_ = nullptr;
  std::uint8_t unit_id_;
  ModbusTransport transport_;
  modbus::HoldingRegisters holding_{};
  modbus::InputRegisters input_{};
  Counter requests_{0};
  Counter answered_{0};
  Counter rejected_{0};
  Counter exceptions_{0};
  Counter computations_{0};
  Counter refused_{0};
  Counter outside_domain_{0};
  Counter clients_connected_{0};
  Counter clients_active_{0};
  Counter clients_refused_{0};
  Counter receive_errors_{0};
  Counter clients_idle_closed_{0};
  Counter clients_evicted_{0};
};

}  // namespace cmmcomp::plugins
