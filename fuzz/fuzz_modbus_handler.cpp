// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the Modbus request handler (plugins/modbus_request_handler.hpp) with
/// the shipped model, fed a sequence of PDUs. Each record is [unit][length n][n PDU bytes].
/// Invariants (abort on violation): every decision is a reply, a documented exception (01, 02,
/// 03, 0B) or silence, and silence only for function codes from 0x80 (TCP); no reply to a code
/// it does not implement; the result block never holds a NaN or an infinity.
#include <cmath>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "shipped_compensator.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;

bool implemented(std::uint8_t fc) {
  return fc == kReadHoldingRegisters || fc == kReadInputRegisters || fc == kWriteSingleRegister ||
         fc == kWriteMultipleRegisters || fc == kReadWriteMultipleRegisters;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static ModbusRequestHandler handler(fuzzing::shipped_compensator(), 1, ModbusTransport::kTcp);
  for (std::size_t at = 0; at + 2 <= size;) {
    const std::uint8_t unit = data[at];
    const std::size_t n = data[at + 1];
    at += 2;
    if (at + n > size) break;
    const std::uint8_t* pdu = data + at;
    at += n;
    const ModbusDecision d = handler.handle(unit, n == 0 ? nullptr : pdu, n);
    switch (d.kind) {
      case ModbusDecision::Kind::kReply:
        if (n == 0 || !implemented(pdu[0])) std::abort();
        break;
      case ModbusDecision::Kind::kException:
        if (d.exception != 0x01 && d.exception != 0x02 && d.exception != 0x03 &&
            d.exception != 0x0B) {
          std::abort();
        }
        break;
      case ModbusDecision::Kind::kSilent:
        if (n == 0 || pdu[0] < 0x80) std::abort();
        break;
      default:
        std::abort();
    }
    const modbus::Result r = modbus::decode_result(handler.input());
    if (!std::isfinite(r.mpe_um) || !std::isfinite(r.rpe_um) || !std::isfinite(r.mae_um) ||
        !std::isfinite(r.rae_um)) {
      std::abort();
    }
    for (const double v : r.correction_um) {
      if (!std::isfinite(v)) std::abort();
    }
  }
  return 0;
}
