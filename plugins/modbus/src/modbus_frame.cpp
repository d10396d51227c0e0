// SPDX-License-Identifier: MIT
/// @file serve_one_frame: the one implementation of "frame in, answer out" with libmodbus.
#include "modbus_frame.hpp"

#include <cstddef>

namespace cmmcomp::plugins::detail {

FrameOutcome serve_one_frame(modbus_t* ctx,
                             int fd,
                             ModbusRequestHandler& handler,
                             modbus_mapping_t& mapping,
                             std::uint8_t* query) {
  modbus_set_socket(ctx, fd);
  const int length = modbus_receive(ctx, query);
  if (length == 0) return FrameOutcome::kIgnored;  // RTU: another unit's frame
  if (length < 0) {
    handler.note_receive_error();
    return FrameOutcome::kReceiveError;
  }
  const int header_length = modbus_get_header_length(ctx);
  // RTU frames end with a 2-byte CRC; a TCP header has 7 bytes, an RTU header 1.
  const int checksum_length = header_length == 7 ? 0 : 2;
  const int pdu_length = length - header_length - checksum_length;
  const ModbusDecision d =
      handler.handle(query[static_cast<std::size_t>(header_length - 1)],
                     query + header_length,
                     pdu_length > 0 ? static_cast<std::size_t>(pdu_length) : 0);
  switch (d.kind) {
    case ModbusDecision::Kind::kReply:
      if (modbus_reply(ctx, query, length, &mapping) < 0) {
        handler.note_reply_failed();
        return FrameOutcome::kSendError;
      }
      return FrameOutcome::kAnswered;
    case ModbusDecision::Kind::kException:
      if (modbus_reply_exception(ctx, query, d.exception) < 0) return FrameOutcome::kSendError;
      return FrameOutcome::kAnswered;
    case ModbusDecision::Kind::kSilent:
      break;
  }
  return FrameOutcome::kSilent;
}

}  // namespace cmmcomp::plugins::detail
