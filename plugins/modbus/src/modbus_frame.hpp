// SPDX-License-Identifier: MIT
/// @file The server's per-frame step — receive one frame with libmodbus, let
/// ModbusRequestHandler decide, answer with modbus_reply or modbus_reply_exception — as one
/// function, so ModbusServer and ModbusTcpAduResponder (replay) run exactly the same code; the
/// MBAP framing check both apply to Modbus TCP; and the loopback through which a complete TCP
/// ADU reaches libmodbus. Private to the plugin: it names libmodbus types.
#pragma once

#include <modbus.h>

#include <array>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstddef>
#include <cstdint>

namespace cmmcomp::plugins::detail {

/// What serve_one_frame did.
enum class FrameOutcome : std::uint8_t {
  kAnswered,      ///< a reply or an exception was sent
  kSilent,        ///< the handler chose not to answer (RTU: another unit, broadcast)
  kIgnored,       ///< libmodbus received nothing to answer (RTU: another unit's frame)
  kReceiveError,  ///< truncated, timed out mid-frame, bad CRC or peer gone (counted)
  kSendError,     ///< the answer could not be sent (counted when it was a reply)
};

/// Receives one frame on `fd` into `query` (MODBUS_MAX_ADU_LENGTH bytes), decides with
/// `handler` and sends the answer on `fd`. `mapping` must point at the handler's images.
FrameOutcome serve_one_frame(modbus_t* ctx,
                             int fd,
                             ModbusRequestHandler& handler,
                             modbus_mapping_t& mapping,
                             std::uint8_t* query);

// ---- Modbus TCP framing (docs/protocol-modbus.md, "Transports and unit id")

/// MBAP header: transaction id (2), protocol id (2, must be 0), length (2: the bytes after it,
/// unit id and PDU), unit id (1).
inline constexpr std::size_t kMbapHeaderLength = 7;
/// The longest Modbus TCP ADU: the header and a 253-byte PDU.
inline constexpr std::size_t kMaxTcpAduLength = 260;

/// What the first bytes of a Modbus TCP stream are.
struct MbapVerdict {
  enum class Kind : std::uint8_t {
    kNeedMore,  ///< a frame so far: `adu_length` is known once the header is complete
    kComplete,  ///< the first `adu_length` bytes are one well-formed ADU
    kInvalid,   ///< not a Modbus TCP frame: `why` says what; the stream cannot be resynchronised
  };
  Kind kind = Kind::kNeedMore;
  std::size_t adu_length = 0;  ///< 6 + the length field, once known
  const char* why = "";
};

/// Judges the `size` bytes a client has sent since its last frame. Invalid: a protocol id
/// other than 0, a length field outside 2..254, or, for the function codes the server
/// implements, a PDU whose own counts disagree with the length field (libmodbus would read
/// another length and the stream would lose its framing). RT-safe.
MbapVerdict judge_mbap(const std::uint8_t* bytes, std::size_t size) noexcept;

/// Sets the timeouts of a context that serves through an AduLoopback: the whole judged frame is
/// queued before libmodbus reads it, so they only bound a frame shorter than its function code
/// says (which judge_mbap already refuses for the codes served): 1 ms.
void set_loopback_timeouts(modbus_t* ctx) noexcept;

/// A local socket pair through which one complete Modbus TCP ADU at a time reaches libmodbus'
/// receive and reply, so that a server assembling frames without blocking still answers with
/// serve_one_frame. Setup throws cmmcomp::Error; serve never allocates.
class AduLoopback {
 public:
  AduLoopback();
  ~AduLoopback();
  AduLoopback(const AduLoopback&) = delete;
  AduLoopback& operator=(const AduLoopback&) = delete;

  /// Serves the complete ADU `adu` (judge_mbap said kComplete for `size`) with `ctx` (a TCP
  /// context whose byte timeout is short: the whole frame is queued before libmodbus reads it)
  /// and copies the answer, if any, to `reply` (`reply_size` bytes).
  FrameOutcome serve(modbus_t* ctx,
                     ModbusRequestHandler& handler,
                     modbus_mapping_t& mapping,
                     std::uint8_t* query,
                     const std::uint8_t* adu,
                     std::size_t size,
                     std::array<std::uint8_t, kMaxTcpAduLength>& reply,
                     std::size_t& reply_size) noexcept;

 private:
  std::array<int, 2> fds_{-1, -1};  // [0] libmodbus' end, [1] the client's
};

}  // namespace cmmcomp::plugins::detail
