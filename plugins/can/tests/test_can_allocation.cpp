// SPDX-License-Identifier: MIT
/// @file The per-frame path allocates nothing: CanRequestHandler::on_frame/on_time and the codec,
/// for answered requests (with and without the interval part), rejects and heartbeats (not built
/// under sanitizers: see CMakeLists.txt).
#include <gtest/gtest.h>

#include <cmmcomp/plugins/can_request_handler.hpp>

#include "can_test_frames.hpp"
#include "support/allocation_counter.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins::can;
using cmmcomp::plugins::CanFrameBatch;
using cmmcomp::plugins::CanRequestHandler;

TEST(CanRequestHandlerRt, HandlingFramesDoesNotAllocate) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(cmmcomp::test::publish_example(comp), Status::kOk);  // with its interval calibration
  CanRequestHandler handler(comp, 0x300, std::chrono::milliseconds(50));
  std::array<RequestFrames, 64> requests;
  for (std::uint32_t s = 0; s < 64; ++s) {
    compensation::MoveRequest m = cmmcomp::test::example_move();
    m.sequence = s;
    // up to 87 mm/s: some outside the range (so U95 grows), none far outside (refused)
    m.pv_mm_s = 5.0 + 1.3 * s;
    // Odd sequences ask for the interval (protocol version 2: a fourth frame).
    ASSERT_EQ(encode_request(m, 0x300, requests[s], nullptr, s % 2 == 1), Status::kOk);
  }
  Frame bad = requests[0][1];
  bad.dlc = 3;
  std::size_t answered = 0;
  std::size_t with_interval = 0;
  std::size_t frames_out = 0;
  cmmcomp::test::AllocationCounter allocations;
  for (int n = 0; n < 10000; ++n) {
    const RequestFrames& r = requests[static_cast<std::size_t>(n % 64)];
    const std::int64_t t = n * 1'000'000LL;
    CanFrameBatch out;
    for (const Frame& f : r) handler.on_frame(f, t, out);
    answered += out.size == kResponseParts || out.size == kResponseParts + 1u ? 1 : 0;
    with_interval += out.size == kResponseParts + 1u ? 1 : 0;
    out.size = 0;
    handler.on_frame(r[0], t, out);
    handler.on_frame(bad, t, out);          // reject path
    handler.on_time(t + 100'000'000, out);  // timeout path
    const HeartbeatInfo h = handler.next_heartbeat();
    frames_out += out.size + encode_heartbeat(h, 1, 0x300).dlc;
  }
  EXPECT_EQ(allocations.count(), 0u);
  EXPECT_EQ(answered, 10000u);
  EXPECT_EQ(with_interval, 5000u);
  EXPECT_GT(frames_out, 0u);
}

}  // namespace
