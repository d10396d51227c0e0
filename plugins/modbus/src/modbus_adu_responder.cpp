// SPDX-License-Identifier: MIT
/// @file ModbusTcpAduResponder: the server's framing check and AduLoopback, one ADU at a time.
#include <fcntl.h>
#include <modbus.h>
#include <sys/socket.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/modbus_adu_responder.hpp>
#include <cstring>
#include <string>

#include "modbus_frame.hpp"

namespace cmmcomp::plugins {

struct ModbusTcpAduResponder::Impl {
  Impl(const compensation::MoveCompensator& compensator, std::uint8_t unit_id)
      : handler(compensator, unit_id, ModbusTransport::kTcp) {
    mapping.tab_registers = handler.holding().data();
    mapping.nb_registers = modbus::kHoldingCount;
    mapping.tab_input_registers = handler.input().data();
    mapping.nb_input_registers = modbus::kInputCount;
    // Never connected: only the framing, the reply builder and the socket slot are used.
    ctx = modbus_new_tcp("127.0.0.1", 502);
    if (ctx == nullptr) {
      throw Error(std::string("Modbus responder: cannot create the context: ") +
                  modbus_strerror(errno));
    }
    detail::set_loopback_timeouts(ctx);
    handler.note_client_connected();  // as the server counts the one connection of a session
  }

  ~Impl() {
    if (ctx != nullptr) {
      modbus_set_socket(ctx, -1);  // the loopback's sockets are closed by it, not by libmodbus
      modbus_free(ctx);
    }
  }

  Answer respond(const std::uint8_t* adu, std::size_t size) {
    Answer a;
    // The server frames a TCP stream with judge_mbap before libmodbus sees it: a request it
    // would drop the connection for is a receive error here.
    const detail::MbapVerdict v = detail::judge_mbap(adu, size);
    if (v.kind != detail::MbapVerdict::Kind::kComplete || v.adu_length != size) {
      handler.note_receive_error();
      a.kind = Answer::Kind::kReceiveError;
      return a;
    }
    std::array<std::uint8_t, detail::kMaxTcpAduLength> reply{};
    std::size_t reply_size = 0;
    const detail::FrameOutcome o =
        loopback.serve(ctx, handler, mapping, query.data(), adu, size, reply, reply_size);
    switch (o) {
      case detail::FrameOutcome::kAnswered:
        a.kind = Answer::Kind::kAnswered;
        a.adu.assign(reply.begin(), reply.begin() + static_cast<std::ptrdiff_t>(reply_size));
        break;
      case detail::FrameOutcome::kReceiveError:
      case detail::FrameOutcome::kSendError:
        a.kind = Answer::Kind::kReceiveError;
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
  detail::AduLoopback loopback;
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
