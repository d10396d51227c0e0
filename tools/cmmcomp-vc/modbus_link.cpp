// SPDX-License-Identifier: MIT
/// @file Modbus TCP client of the virtual controller.
#include "modbus_link.hpp"

#include <modbus.h>

#include <cerrno>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstring>

#include "modbus_relay.hpp"
#include "recording_format.hpp"

namespace cmmcomp::vc {

namespace map = plugins::modbus;

struct ModbusLink::Impl {
  std::unique_ptr<ModbusRecordingRelay> relay;
  modbus_t* ctx = nullptr;
};

ModbusLink::ModbusLink(std::string label,
                       const std::string& endpoint,
                       int unit_id,
                       int timeout_ms,
                       const std::string& record_path)
    : label_(std::move(label)), where_("modbus " + endpoint), impl_(std::make_unique<Impl>()) {
  // The agent's own endpoint grammar (brackets for IPv6 included); a controller talks TCP.
  const plugins::ModbusEndpoint where = plugins::ModbusEndpoint::parse(endpoint);
  if (where.kind != plugins::ModbusEndpoint::Kind::kTcp) {
    throw ConfigError("Modbus endpoint '" + endpoint + "': expected tcp:HOST:PORT");
  }
  const std::string& host = where.host;
  const int port = where.port;
  if (unit_id < 1 || unit_id > 255) throw ConfigError("--modbus-unit must be 1 … 255");
  if (!record_path.empty()) {
    impl_->relay = std::make_unique<ModbusRecordingRelay>(
        host, port, record_path, modbus_transcript_header(label_, unit_id));
    impl_->ctx = modbus_new_tcp("127.0.0.1", impl_->relay->port());
  } else {
    impl_->ctx = modbus_new_tcp_pi(host.c_str(), std::to_string(port).c_str());
  }
  modbus_t* ctx = impl_->ctx;
  if (ctx == nullptr) throw Error("libmodbus: cannot create a TCP context for " + endpoint);
  modbus_set_slave(ctx, unit_id);
  const auto ms = static_cast<std::uint32_t>(timeout_ms);
  modbus_set_response_timeout(ctx, ms / 1000, (ms % 1000) * 1000);
  if (modbus_connect(ctx) != 0) {
    const std::string why = modbus_strerror(errno);
    modbus_free(ctx);
    impl_->ctx = nullptr;
    throw UnreachableError("agent '" + label_ + "' at " + endpoint + " unreachable: " + why);
  }
}

ModbusLink::~ModbusLink() {
  if (impl_->ctx != nullptr) {
    modbus_close(impl_->ctx);
    modbus_free(impl_->ctx);
  }
  impl_->relay.reset();  // after the client closed: the relay sees the end of the session
}

Answer ModbusLink::ask(const compensation::MoveRequest& move) {
  compensation::MoveRequest m = move;
  m.sequence = ++sequence_;
  map::HoldingRegisters h{};
  map::encode_request(m, h);
  // One FC23: write the request, read its result and interval (holding 25-57, protocol
  // version 2: docs/protocol-modbus.md).
  constexpr int kWords = map::kResultWords + map::kIntervalWords;
  std::array<std::uint16_t, kWords> copy{};
  const int got = modbus_write_and_read_registers(
      impl_->ctx, 0, map::kRequestCount, h.data(), map::kResultCopy, kWords, copy.data());
  Answer a;
  if (got != kWords) {
    const int e = errno;
    if (got < 0 && e > MODBUS_ENOBASE && e < MODBUS_ENOBASE + 0x20) {
      // An exception answer: the agent refused the request; the controller probes on.
      a.note = std::string("modbus exception: ") + modbus_strerror(e);
      a.status = -1;
      return a;
    }
    throw Error("agent '" + label_ + "' (" + where_ +
                "): " + (got < 0 ? std::string(modbus_strerror(e)) : "short answer"));
  }
  map::InputRegisters in{};
  std::copy(copy.begin(), copy.begin() + map::kResultWords, in.begin() + map::kResultSequence);
  std::copy(copy.begin() + map::kResultWords, copy.end(), in.begin() + map::kIntervalFlags);
  const map::Result r = map::decode_result(in);
  a.status = r.status;
  a.flags = r.flags;
  a.rae_um = r.rae_um;
  a.correction_um = r.correction_um;
  a.model_id = r.model_id;
  a.u95_um = r.u95_um;
  a.interval_flags = r.interval_flags;
  if (r.sequence != m.sequence) {
    a.note = "sequence mismatch";
  } else if ((r.flags & compensation::kFlagOk) == 0) {
    a.note = "flags without OK";
  } else {
    a.usable = true;
  }
  return a;
}

}  // namespace cmmcomp::vc
