// SPDX-License-Identifier: MIT
/// @file HIL: the real CanServer on a real vcan bus (run inside scripts/uml-run.sh), with a raw
/// socket of its own as the controller: answers, kernel filter, rejects, heartbeat, hot swap.
#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cmmcomp/plugins/can_server.hpp>
#include <memory>
#include <thread>

#include "can_example_result.hpp"
#include "can_peer.hpp"
#include "can_test_frames.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins::can;
using cmmcomp::plugins::CanCounters;
using cmmcomp::plugins::CanServer;
using cmmcomp::plugins::CanServerOptions;
using cmmcomp::test::CanPeer;

constexpr int kWaitMs = 1000;  // generous: every syscall is slow under UML

class CanServerHil : public ::testing::Test {
 protected:
  void start(CanServerOptions o = {}) {
    if (o.heartbeat_period == CanServerOptions{}.heartbeat_period) {
      o.heartbeat_period = std::chrono::milliseconds(0);  // off unless a test wants it
    }
    ASSERT_EQ(cmmcomp::test::publish_example(comp_), Status::kOk);  // calibrated
    server_ = std::make_unique<CanServer>(comp_, o);
    base_ = o.base_id;
    peer_ = std::make_unique<CanPeer>(o.interface, o.base_id, o.fd);
    thread_ = std::thread([this] { server_->run(stop_); });
  }
  void TearDown() override {
    stop_.store(true);
    if (thread_.joinable()) thread_.join();
  }

  RequestFrames request(std::uint32_t sequence, double pv_mm_s = 42.5) const {
    compensation::MoveRequest m = cmmcomp::test::example_move();
    m.sequence = sequence;
    m.pv_mm_s = pv_mm_s;
    RequestFrames f;
    EXPECT_EQ(encode_request(m, base_, f), Status::kOk);
    return f;
  }

  bool send_all(const RequestFrames& f) const {
    return peer_->send(f[0]) && peer_->send(f[1]) && peer_->send(f[2]);
  }

  bool receive_response(DecodedResponse& d) const {
    ResponseFrames r;
    for (Frame& f : r) {
      if (!peer_->receive_except(f, base_ + kHeartbeatOffset, kWaitMs)) return false;
    }
    return decode_response(r, base_, d);
  }

  bool receive_reject(RejectInfo& r) const {
    Frame f;
    return peer_->receive_except(f, base_ + kHeartbeatOffset, kWaitMs) &&
           decode_reject(f, base_, r);
  }

  compensation::MoveCompensator comp_;
  std::unique_ptr<CanServer> server_;
  std::unique_ptr<CanPeer> peer_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
  std::uint32_t base_ = kDefaultBaseId;
};

TEST_F(CanServerHil, AnswersARequestWithTheClosedFormCorrection) {
  start();
  EXPECT_EQ(server_->where(), "SocketCAN vcan0, base id 0x300");
  ASSERT_TRUE(send_all(request(5)));
  DecodedResponse d;
  ASSERT_TRUE(receive_response(d));
  cmmcomp::test::expect_example_response(d);
}

// Protocol version 2: WantInterval gets the three frames of version 1 and part 3 (the document's
// second example), in order, on the real bus.
TEST_F(CanServerHil, AnswersAnIntervalRequestWithFourFrames) {
  start();
  RequestFrames f;
  ASSERT_EQ(encode_request(cmmcomp::test::example_interval_move(), base_, f, nullptr, true),
            Status::kOk);
  ASSERT_TRUE(send_all(f));
  DecodedResponse d;
  ASSERT_TRUE(receive_response(d));
  Frame interval;
  ASSERT_TRUE(peer_->receive_except(interval, base_ + kHeartbeatOffset, kWaitMs));
  ASSERT_TRUE(decode_interval(interval, base_, d)) << cmmcomp::test::to_text(interval);
  cmmcomp::test::expect_example_interval_response(d);
  EXPECT_EQ(server_->counters().intervals, 1u);
  // ... and nothing more.
  Frame extra;
  EXPECT_FALSE(peer_->receive_except(extra, base_ + kHeartbeatOffset, 200));
}

TEST_F(CanServerHil, KernelFilterKeepsOtherIdentifiersAway) {
  start();
  Frame other = request(1)[0];
  for (std::uint32_t id : {0x123u, 0x301u, 0x302u, 0x304u, 0x2FFu}) {
    other.id = id;
    ASSERT_TRUE(peer_->send(other));
  }
  other.id = 0x300;
  ASSERT_TRUE(peer_->send(other, CAN_EFF_FLAG));  // extended 0x00000300
  ASSERT_TRUE(peer_->send(other, CAN_RTR_FLAG));  // remote frame on the request id
  ASSERT_TRUE(send_all(request(6)));
  DecodedResponse d;
  ASSERT_TRUE(receive_response(d));
  EXPECT_EQ(d.correction.sequence, 6u);
  const CanCounters c = server_->counters();
  EXPECT_EQ(c.frames_in, 3u);
  EXPECT_EQ(c.ignored, 0u);  // the kernel dropped them before the server saw them
  EXPECT_EQ(c.answered, 1u);
  EXPECT_EQ(c.rejected, 0u);
}

TEST_F(CanServerHil, MalformedAndPartialRequestsGetRejects) {
  start();
  const RequestFrames f = request(9);
  Frame shortened = f[0];
  shortened.dlc = 5;
  ASSERT_TRUE(peer_->send(shortened));
  RejectInfo r;
  ASSERT_TRUE(receive_reject(r));
  EXPECT_EQ(r.reason, RejectReason::kWrongDlc);
  EXPECT_EQ(r.sequence, 9);

  ASSERT_TRUE(peer_->send(f[1]));  // part 1 without part 0
  ASSERT_TRUE(receive_reject(r));
  EXPECT_EQ(r.reason, RejectReason::kMissingPart);

  Frame unknown = f[0];
  unknown.data[0] = static_cast<std::uint8_t>(unknown.data[0] | 3);
  ASSERT_TRUE(peer_->send(unknown));
  ASSERT_TRUE(receive_reject(r));
  EXPECT_EQ(r.reason, RejectReason::kUnknownPart);

  ASSERT_TRUE(peer_->send(f[0]));  // and nothing more: the part timeout (50 ms) expires
  const auto t0 = std::chrono::steady_clock::now();
  ASSERT_TRUE(receive_reject(r));
  const auto waited = std::chrono::steady_clock::now() - t0;
  EXPECT_EQ(r.reason, RejectReason::kTimeout);
  EXPECT_EQ(r.part, 1);
  EXPECT_GE(waited, std::chrono::milliseconds(40));
  EXPECT_LT(waited, std::chrono::milliseconds(2000));  // loose: UML on a loaded machine
  const CanCounters c = server_->counters();
  EXPECT_EQ(c.malformed, 3u);
  EXPECT_EQ(c.timeouts, 1u);
  EXPECT_EQ(c.rejected, 4u);
  EXPECT_EQ(c.answered, 0u);
}

TEST_F(CanServerHil, HeartbeatCarriesModelIdAndCounters) {
  CanServerOptions o;
  o.heartbeat_period = std::chrono::milliseconds(100);
  start(o);
  ASSERT_TRUE(send_all(request(1)));
  DecodedResponse d;
  ASSERT_TRUE(receive_response(d));
  // Wait for a heartbeat sent after the answer: page 0 with answered = 1.
  HeartbeatInfo h;
  bool counted = false, id_seen = false;
  for (int i = 0; i < 40 && !(counted && id_seen); ++i) {
    Frame f;
    ASSERT_TRUE(peer_->receive(f, kWaitMs));
    const int page = decode_heartbeat(f, base_, h);
    counted = counted || (page == 0 && h.answered == 1 && h.requests == 1 && h.model_mask == 1 &&
                          h.protocol_version == kProtocolVersion);
    id_seen = id_seen || (page == 1 && h.model_ids[0] == cmmcomp::test::kExampleModelId);
  }
  EXPECT_TRUE(counted);
  EXPECT_TRUE(id_seen);
  EXPECT_GE(server_->counters().heartbeats, 2u);
}

TEST_F(CanServerHil, HotSwapShowsInTheNextAnswer) {
  start();
  ASSERT_TRUE(send_all(request(1)));
  DecodedResponse d;
  ASSERT_TRUE(receive_response(d));
  EXPECT_EQ(d.correction.model_id, cmmcomp::test::kExampleModelId);
  ASSERT_EQ(comp_.publish(0, cmmcomp::test::linear_model({1, 1, 1, -2}, {0, 0, 0, 0}), 0x77),
            Status::kOk);
  ASSERT_TRUE(send_all(request(2)));
  ASSERT_TRUE(receive_response(d));
  EXPECT_EQ(d.correction.model_id, 0x77u);
  EXPECT_DOUBLE_EQ(d.correction.rae_um, -2.0);
  EXPECT_DOUBLE_EQ(d.correction.correction_um[0], 2.0);
}

TEST_F(CanServerHil, ManyRoundTripsAllAnsweredInOrder) {
  start();
  for (std::uint32_t n = 0; n < 300; ++n) {
    const double pv = 5.0 + (n % 76);
    ASSERT_TRUE(send_all(request(n % 64, pv)));
    DecodedResponse d;
    ASSERT_TRUE(receive_response(d)) << n;
    ASSERT_EQ(d.correction.sequence, n % 64);
    ASSERT_NEAR(d.correction.mpe_um, 3.0 + (pv - 5.0) / 75.0, 0.005 + 1e-9);
  }
  EXPECT_EQ(server_->counters().answered, 300u);
  EXPECT_EQ(server_->counters().rejected, 0u);
}

TEST_F(CanServerHil, ConfigurableBaseIdOnTheSecondBus) {
  CanServerOptions o;
  o.interface = "vcan1";
  o.base_id = 0x120;
  start(o);
  EXPECT_EQ(server_->where(), "SocketCAN vcan1, base id 0x120");
  ASSERT_TRUE(send_all(request(3)));
  DecodedResponse d;
  ASSERT_TRUE(receive_response(d));
  EXPECT_EQ(d.correction.sequence, 3u);
}

TEST_F(CanServerHil, StopIsNoticedPromptly) {
  start();
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  const auto t0 = std::chrono::steady_clock::now();
  stop_.store(true);
  thread_.join();
  // run() waits at most 100 ms in ppoll; the rest is slack for UML on a loaded machine.
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::milliseconds(400));
}

// vcan1 has the CAN FD MTU (scripts/uml-run.sh): FD requests get FD answers, classic ones
// classic answers, and an FD frame longer than 8 bytes is a wrong-DLC reject.
TEST_F(CanServerHil, CanFdRequestsAreAnsweredInCanFd) {
  CanServerOptions o;
  o.interface = "vcan1";
  o.fd = true;
  start(o);
  EXPECT_EQ(server_->where(), "SocketCAN vcan1 (CAN FD), base id 0x300");
  const RequestFrames f = request(4);
  for (const Frame& x : f) ASSERT_TRUE(peer_->send(x, 0, true));
  ResponseFrames r;
  for (Frame& x : r) {
    bool was_fd = false;
    ASSERT_TRUE(peer_->receive(x, kWaitMs, &was_fd));
    EXPECT_TRUE(was_fd);
  }
  DecodedResponse d;
  ASSERT_TRUE(decode_response(r, base_, d));
  EXPECT_EQ(d.correction.sequence, 4u);
  EXPECT_DOUBLE_EQ(d.correction.rae_um, 3.5);

  ASSERT_TRUE(send_all(request(5)));  // classic frames on the same bus
  bool was_fd = true;
  ASSERT_TRUE(peer_->receive(r[0], kWaitMs, &was_fd));
  EXPECT_FALSE(was_fd);
  ASSERT_TRUE(peer_->receive(r[1], kWaitMs) && peer_->receive(r[2], kWaitMs));
  ASSERT_TRUE(decode_response(r, base_, d));
  EXPECT_EQ(d.correction.sequence, 5u);

  // WantInterval in CAN FD: all four response frames in CAN FD.
  RequestFrames asking;
  ASSERT_EQ(encode_request(cmmcomp::test::example_interval_move(), base_, asking, nullptr, true),
            Status::kOk);
  for (const Frame& x : asking) ASSERT_TRUE(peer_->send(x, 0, true));
  std::array<Frame, kResponseParts + 1> four;
  for (Frame& x : four) {
    bool fd_answer = false;
    ASSERT_TRUE(peer_->receive(x, kWaitMs, &fd_answer));
    EXPECT_TRUE(fd_answer);
  }
  ASSERT_TRUE(decode_response({four[0], four[1], four[2]}, base_, d));
  ASSERT_TRUE(decode_interval(four[3], base_, d));
  cmmcomp::test::expect_example_interval_response(d);

  Frame long_frame = f[0];
  long_frame.dlc = 12;
  ASSERT_TRUE(peer_->send(long_frame, 0, true));
  Frame reject_frame;
  ASSERT_TRUE(peer_->receive(reject_frame, kWaitMs, &was_fd));
  EXPECT_TRUE(was_fd);
  RejectInfo rj;
  ASSERT_TRUE(decode_reject(reject_frame, base_, rj));
  EXPECT_EQ(rj.reason, RejectReason::kWrongDlc);
  EXPECT_EQ(rj.sequence, 4);
}

TEST(CanServerHilSetup, CanFdNeedsACanFdInterface) {
  compensation::MoveCompensator comp;
  CanServerOptions o;
  o.interface = "vcan0";  // classic MTU
  o.fd = true;
  try {
    CanServer server(comp, o);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_STREQ(
        e.what(),
        "vcan0 is not a CAN FD interface (MTU 16, CAN FD needs 72: ip link set vcan0 mtu 72)");
  }
}

TEST(CanServerHilSetup, NamesAMissingInterface) {
  compensation::MoveCompensator comp;
  CanServerOptions o;
  o.interface = "vcan9";
  try {
    CanServer server(comp, o);
    FAIL() << "no exception";
  } catch (const Error& e) {
    EXPECT_STREQ(e.what(), "no such interface vcan9");
  }
}

}  // namespace
