// SPDX-License-Identifier: MIT
/// @file Answers Modbus TCP ADUs in process, with the server's own code path: the request bytes
/// go through libmodbus' receive, ModbusRequestHandler::handle and modbus_reply exactly as in
/// ModbusServer, only over a local socket pair instead of a network connection. Replay
/// (tools/cmmcomp-replay) uses it to check recorded sessions byte for byte.
///
/// libmodbus types stay in the .cpp (dependency wall: only plugins see libmodbus).
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

namespace cmmcomp::plugins {

/// One in-process Modbus TCP server session (one client connected), answering one ADU at a
/// time. Not thread-safe.
class ModbusTcpAduResponder {
 public:
  /// What one request produced.
  struct Answer {
    enum class Kind : std::uint8_t {
      kAnswered,      ///< `adu` holds the reply or exception ADU the server sent
      kSilent,        ///< the server sent nothing
      kReceiveError,  ///< libmodbus could not receive the bytes as one frame (the server would
                      ///< drop the connection); `adu` is empty
    };
    Kind kind = Kind::kSilent;
    std::vector<std::uint8_t> adu;
  };

  /// `compensator` must outlive the responder; `unit_id` as ModbusServerOptions::unit_id.
  /// Setup only. Throws cmmcomp::Error when the socket pair or the libmodbus context cannot be
  /// created.
  explicit ModbusTcpAduResponder(const compensation::MoveCompensator& compensator,
                                 std::uint8_t unit_id = 1);
  ~ModbusTcpAduResponder();
  ModbusTcpAduResponder(const ModbusTcpAduResponder&) = delete;
  ModbusTcpAduResponder& operator=(const ModbusTcpAduResponder&) = delete;

  /// Answers the request ADU `adu` (MBAP header and PDU, at most 260 bytes) as ModbusServer
  /// would on a TCP connection. Bytes libmodbus did not consume are discarded, so the next
  /// request starts clean. Not RT-safe (allocates the answer; for tools and tests).
  Answer respond(const std::uint8_t* adu, std::size_t size);

  /// The handler (its counters and register images).
  const ModbusRequestHandler& handler() const noexcept;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace cmmcomp::plugins
