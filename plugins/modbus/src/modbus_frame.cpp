// SPDX-License-Identifier: MIT
/// @file serve_one_frame: the one implementation of "frame in, answer out" with libmodbus.
#include "modbus_frame.hpp"

#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <cstring>
#include <string>

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

namespace {

std::size_t be16(const std::uint8_t* p) noexcept {
  return (static_cast<std::size_t>(p[0]) << 8) | p[1];
}

/// Reads what is queued on non-blocking `fd` into `out` (up to `capacity`; the rest is
/// discarded); returns the bytes kept.
std::size_t drain(int fd, std::uint8_t* out, std::size_t capacity) noexcept {
  std::array<std::uint8_t, 512> buffer{};
  std::size_t kept = 0;
  while (true) {
    const ssize_t n = ::recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
    if (n <= 0) return kept;
    for (ssize_t i = 0; i < n && kept < capacity; ++i)
      out[kept++] = buffer[static_cast<std::size_t>(i)];
  }
}

}  // namespace

MbapVerdict judge_mbap(const std::uint8_t* bytes, std::size_t size) noexcept {
  MbapVerdict v;
  const auto invalid = [&v](const char* why) {
    v.kind = MbapVerdict::Kind::kInvalid;
    v.why = why;
    return v;
  };
  if (size >= 4 && (bytes[2] != 0 || bytes[3] != 0)) return invalid("protocol id is not 0");
  if (size < 6) return v;
  const std::size_t length = be16(bytes + 4);
  if (length < 2 || length > kMaxTcpAduLength - 6) {
    return invalid("MBAP length outside 2..254");
  }
  v.adu_length = 6 + length;
  if (size < v.adu_length) return v;
  // The PDU's own length, for the function codes served (others are answered with exception
  // 01 and need no length of their own).
  const std::uint8_t* pdu = bytes + kMbapHeaderLength;
  const std::size_t pdu_length = length - 1;
  std::size_t expected = 0;
  switch (pdu[0]) {
    case kReadHoldingRegisters:
    case kReadInputRegisters:
    case kWriteSingleRegister:
      expected = 5;
      break;
    case kWriteMultipleRegisters:
      expected = pdu_length >= 6 ? 6 + std::size_t{pdu[5]} : 6;
      break;
    case kReadWriteMultipleRegisters:
      expected = pdu_length >= 10 ? 10 + std::size_t{pdu[9]} : 10;
      break;
    default:
      expected = pdu_length;
  }
  if (expected != pdu_length) return invalid("MBAP length disagrees with the PDU");
  v.kind = MbapVerdict::Kind::kComplete;
  return v;
}

void set_loopback_timeouts(modbus_t* ctx) noexcept {
  modbus_set_indication_timeout(ctx, 0, 1000);
  modbus_set_byte_timeout(ctx, 0, 1000);
}

AduLoopback::AduLoopback() {
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0, fds_.data()) != 0) {
    throw Error(std::string("Modbus: socketpair failed: ") + std::strerror(errno));
  }
}

AduLoopback::~AduLoopback() {
  for (int fd : fds_) {
    if (fd >= 0) ::close(fd);
  }
}

FrameOutcome AduLoopback::serve(modbus_t* ctx,
                                ModbusRequestHandler& handler,
                                modbus_mapping_t& mapping,
                                std::uint8_t* query,
                                const std::uint8_t* adu,
                                std::size_t size,
                                std::array<std::uint8_t, kMaxTcpAduLength>& reply,
                                std::size_t& reply_size) noexcept {
  reply_size = 0;
  // At most 260 bytes into an empty socket buffer: never short.
  if (::send(fds_[1], adu, size, MSG_NOSIGNAL | MSG_DONTWAIT) != static_cast<ssize_t>(size)) {
    handler.note_receive_error();
    return FrameOutcome::kReceiveError;
  }
  const FrameOutcome o = serve_one_frame(ctx, fds_[0], handler, mapping, query);
  std::uint8_t discard = 0;
  drain(fds_[0], &discard, 0);  // what libmodbus left of the request (nothing, once judged)
  reply_size = drain(fds_[1], reply.data(), reply.size());
  return o;
}

}  // namespace cmmcomp::plugins::detail
