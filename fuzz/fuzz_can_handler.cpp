// SPDX-License-Identifier: MIT
/// @file libFuzzer target: the CAN request handler (plugins/can_request_handler.hpp) with the
/// shipped model, fed a sequence of frames and clock steps. Each 11-byte record is one frame:
/// [0] identifier offset from the base (low 3 bits; 0 is a request part), and whether the clock
/// jumps (bit 3: to the far end of int64, where the deadline must saturate); [1] the DLC
/// (any value); [2..9] data; [10] the time step in ms. Invariants (abort on violation): at most
/// CanFrameBatch::kCapacity frames per call, each with the handler's own identifiers and DLC 8;
/// a request is answered only when all three parts came; the counters add up.
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/plugins/can_request_handler.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <limits>

#include "shipped_compensator.hpp"

namespace {

using namespace cmmcomp;
namespace can = cmmcomp::plugins::can;

void check(const plugins::CanFrameBatch& out) {
  if (out.size > plugins::CanFrameBatch::kCapacity) std::abort();
  for (std::size_t i = 0; i < out.size; ++i) {
    const can::Frame& f = out.frames[i];
    if (f.dlc != can::kFrameDlc) std::abort();
    if (f.id != can::kDefaultBaseId + can::kResponseOffset &&
        f.id != can::kDefaultBaseId + can::kRejectOffset) {
      std::abort();
    }
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  plugins::CanRequestHandler handler(
      fuzzing::shipped_compensator(), can::kDefaultBaseId, std::chrono::milliseconds(50));
  std::int64_t now = 0;
  std::uint64_t request_parts_seen = 0;
  constexpr std::size_t kRecord = 11;
  for (std::size_t at = 0; at + kRecord <= size; at += kRecord) {
    const std::uint8_t* r = data + at;
    can::Frame f;
    f.id = can::kDefaultBaseId + (r[0] & 7u);
    f.dlc = r[1];
    for (std::size_t k = 0; k < 8; ++k) f.data[k] = r[2 + k];
    if ((r[0] & 8u) != 0) {
      now = std::numeric_limits<std::int64_t>::max() - 1000000;
    } else if (now < std::numeric_limits<std::int64_t>::max() - 1000000000) {
      now += std::int64_t{r[10]} * 1000000;
    }
    plugins::CanFrameBatch out;
    handler.on_frame(f, now, out);
    check(out);
    if ((r[0] & 7u) == 0) ++request_parts_seen;
    plugins::CanFrameBatch tick;
    handler.on_time(now, tick);
    check(tick);
  }
  const plugins::CanCounters c = handler.counters();
  if (c.frames_in != request_parts_seen) std::abort();
  if (c.answered > c.requests || 3 * c.requests > c.frames_in) std::abort();
  return 0;
}
