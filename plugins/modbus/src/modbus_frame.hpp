// SPDX-License-Identifier: MIT
/// @file The server's per-frame step — receive one frame with libmodbus, let
/// ModbusRequestHandler decide, answer with modbus_reply or modbus_reply_exception — as one
/// function, so ModbusServer (on its sockets) and ModbusTcpAduResponder (on a socketpair, for
/// replay) run exactly the same code. Private to the plugin: it names libmodbus types.
#pragma once

#include <modbus.h>

#include <cmmcomp/plugins/modbus_request_handler.hpp>
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

}  // namespace cmmcomp::plugins::detail
