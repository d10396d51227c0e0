// SPDX-License-Identifier: MIT
/// @file libFuzzer target: Modbus TCP ADUs through the server's own path, framing check,
/// libmodbus receive, handler and libmodbus reply (ModbusTcpAduResponder, as replay and, frame
/// by frame, ModbusServer use it). The input is split into ADUs at the lengths their MBAP
/// headers announce (or, for a header that announces nothing usable, taken whole). Invariants
/// (abort on violation): an answer is a well-formed ADU of at most 260 bytes that echoes the
/// request's transaction id, protocol id 0 and unit id, and answers its function code (or
/// code | 0x80 for an exception, for codes below 0x80 only).
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/plugins/modbus_adu_responder.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "shipped_compensator.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;

void check(const std::uint8_t* q, std::size_t qn, const ModbusTcpAduResponder::Answer& a) {
  if (a.kind != ModbusTcpAduResponder::Answer::Kind::kAnswered) {
    if (!a.adu.empty()) std::abort();
    return;
  }
  const std::size_t n = a.adu.size();
  if (n < 9 || n > 260 || qn < 8) std::abort();
  const std::size_t length = (std::size_t{a.adu[4]} << 8) | a.adu[5];
  if (length + 6 != n) std::abort();
  if (a.adu[0] != q[0] || a.adu[1] != q[1] || a.adu[2] != 0 || a.adu[3] != 0) std::abort();
  if (a.adu[6] != q[6]) std::abort();
  const std::uint8_t fc = q[7];
  if (fc >= 0x80) std::abort();  // never answered
  if (a.adu[7] != fc && a.adu[7] != (fc | 0x80)) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static ModbusTcpAduResponder responder(fuzzing::shipped_compensator(), 1);
  std::size_t at = 0;
  while (at < size) {
    std::size_t n = size - at;
    if (n >= 6) {
      const std::size_t announced = 6 + ((std::size_t{data[at + 4]} << 8) | data[at + 5]);
      if (announced >= 7 && announced <= n) n = announced;
    }
    if (n > 300) n = 300;
    const ModbusTcpAduResponder::Answer a = responder.respond(data + at, n);
    check(data + at, n, a);
    at += n;
  }
  return 0;
}
