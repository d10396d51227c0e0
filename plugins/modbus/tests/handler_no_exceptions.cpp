// SPDX-License-Identifier: MIT
/// @file Compiled with -fno-exceptions -fno-rtti: the Modbus per-request path (register map and
/// ModbusRequestHandler) needs neither. Exits 0 when the worked example's request gives the
/// documented result and a NaN write is refused with exception 03, changing nothing.
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstdint>
#include <cstdio>
#include <limits>

#include "modbus_example.hpp"

namespace {

namespace map = cmmcomp::plugins::modbus;

/// An FC16 PDU writing holding registers 0 .. 24 from `h` into `pdu`; returns its length.
std::size_t write_pdu(const map::HoldingRegisters& h, std::uint8_t* pdu) {
  pdu[0] = cmmcomp::plugins::kWriteMultipleRegisters;
  pdu[1] = 0;
  pdu[2] = 0;
  pdu[3] = 0;
  pdu[4] = map::kRequestCount;
  pdu[5] = 2 * map::kRequestCount;
  for (std::size_t i = 0; i < map::kRequestCount; ++i) {
    pdu[6 + 2 * i] = static_cast<std::uint8_t>(h[i] >> 8);
    pdu[7 + 2 * i] = static_cast<std::uint8_t>(h[i] & 0xFF);
  }
  return 6 + 2 * map::kRequestCount;
}

}  // namespace

int main() {
  using namespace cmmcomp;
  compensation::MoveCompensator comp;
  const auto model = test::example_model();
  if (comp.publish(0, model, test::kExampleModelId) != Status::kOk) return 1;
  plugins::ModbusRequestHandler handler(comp, 1, plugins::ModbusTransport::kTcp);

  const compensation::MoveRequest m = test::example_request();
  map::HoldingRegisters h{};
  map::encode_request(m, h);
  std::uint8_t pdu[6 + 2 * map::kRequestCount];
  std::size_t n = write_pdu(h, pdu);
  if (handler.handle(1, pdu, n).kind != plugins::ModbusDecision::Kind::kReply) return 2;
  const map::Result r = map::decode_result(handler.input());
  if (r.sequence != 7 || r.flags != compensation::kFlagOk || r.rae_um != 2.0 ||
      r.correction_um[2] != static_cast<double>(-1.6f)) {
    return 3;
  }
  map::put_f32(&h[map::kPv], std::numeric_limits<float>::quiet_NaN());
  h[map::kSequence] = 8;
  n = write_pdu(h, pdu);
  const plugins::ModbusDecision d = handler.handle(1, pdu, n);
  if (d.kind != plugins::ModbusDecision::Kind::kException ||
      d.exception != plugins::kIllegalDataValue) {
    return 4;
  }
  if (map::decode_result(handler.input()).sequence != 7) return 5;
  std::puts("modbus_handler_no_exceptions: ok");
  return 0;
}
