// SPDX-License-Identifier: MIT
/// @file ModbusTcpAduResponder: serve_one_frame over a socket pair.
#include <fcntl.h>
#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmmcomp/error.hpp>
#include <cmmcomp/plugins/modbus_adu_responder.hpp>
#include <cstring>
#include <string>

#include "modbus_frame.hpp"

namespace cmmcomp::plugins {

namespace {

/// Reads everything queued on non-blocking `fd` (appending to `out` when given).
void drain(int fd, std::vector<std::uint8_t>* out) {
  std::array<std::uint8_t, 512> buffer{};
  while (true) {
    const ssize_t n = ::recv(fd, buffer.data(), buffer.size(), MSG_DONTWAIT);
    if (n <= 0) return;
    if (out != nullptr) out->insert(out->end(), buffer.begin(), buffer.begin() + n);
  }
}

}  // namespace

struct ModbusTcpAduResponder::Impl {
  Impl(const compensation::MoveCompensator& compensator, std::uint8_t unit_id)
      : handler(compensator, unit_id, ModbusTransport::kTcp) {
    mapping.tab_registers = handler.holding().data();
    mapping.nb_registers = modbus_map::kHoldingCount;
    mapping.tab_input_registers = handler.input().data();
    mapping.nb_input_registers = modbus_map::kInputCount;
    if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds.data()) != 0) {
      throw Error(std::string("Modbus responder: socketpair failed: ") + std::strerror(errno));
    }
    // Never connected: only the framing, the reply builder and the socket slot are used.
    ctx = modbus_new_tcp("127.0.0.1", 502);
    if (ctx == nullptr) {
      throw Error(std::string("Modbus responder: cannot create the context: ") +
                  modbus_strerror(errno));
    }
    // The whole request is queued before libmodbus reads it: a short timeout only bounds a
    // request shorter than its function code says.
    modbus_set_indication_timeout(ctx, 0, 100000);
    modbus_set_byte_timeout(ctx, 0, 100000);
    handler.note_client_connected();  // as the server counts the one connection of a session
  }

  ~Impl() {
    if (ctx != nullptr) {
      modbus_set_socket(ctx, -1);  // the pair is closed below, not by libmodbus
      modbus_free(ctx);
    }
    for (int fd : fds) {
      if (fd >= 0) ::close(fd);
    }
  }

  Answer respond(const std::uint8_t* adu, std::size_t size) {
    Answer a;
    if (size > MODBUS_TCP_MAX_ADU_LENGTH) {
      a.kind = Answer::Kind::kReceiveError;
      return a;
    }
    if (::send(fds[1], adu, size, MSG_NOSIGNAL) != static_cast<ssize_t>(size)) {
      throw Error(std::string("Modbus responder: send failed: ") + std::strerror(errno));
    }
    const detail::FrameOutcome o =
        detail::serve_one_frame(ctx, fds[0], handler, mapping, query.data());
    drain(fds[0], nullptr);  // what libmodbus left of the request
    drain(fds[1], &a.adu);
    switch (o) {
      case detail::FrameOutcome::kAnswered:
        a.kind = Answer::Kind::kAnswered;
        break;
      case detail::FrameOutcome::kReceiveError:
      case detail::FrameOutcome::kSendError:
        a.kind = Answer::Kind::kReceiveError;
        a.adu.clear();
        break;
      case detail::FrameOutcome::kSilent:
      case detail::FrameOutcome::kIgnored:
        a.kind = Answer::Kind::kSilent;
        break;
    }
    return a;
  }

  ModbusRequestHandler handler;
  modbus_mapping_t mapping{};
  modbus_t* ctx = nullptr;
  std::array<int, 2> fds{-1, -1};  // [0] the server's end, [1] the client's
  std::array<std::uint8_t, MODBUS_MAX_ADU_LENGTH> query{};
};

ModbusTcpAduResponder::ModbusTcpAduResponder(const compensation::MoveCompensator& compensator,
                                             std::uint8_t unit_id)
    : impl_(std::make_unique<Impl>(compensator, unit_id)) {}

ModbusTcpAduResponder::~ModbusTcpAduResponder() = default;

ModbusTcpAduResponder::Answer ModbusTcpAduResponder::respond(const std::uint8_t* adu,
                                                             std::size_t size) {
  return impl_->respond(adu, size);
}

const ModbusRequestHandler& ModbusTcpAduResponder::handler() const noexcept {
  return impl_->handler;
}

}  // namespace cmmcomp::plugins
