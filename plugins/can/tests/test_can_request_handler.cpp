// SPDX-License-Identifier: MIT
/// @file The reassembly state machine with fake frames in and frames out: every framing rule of
/// docs/protocol-can.md ("Reassembly") and the counters.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/plugins/can_request_handler.hpp>
#include <limits>
#include <vector>

#include "can_test_frames.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins::can;
using cmmcomp::plugins::CanCounters;
using cmmcomp::plugins::CanFrameBatch;
using cmmcomp::plugins::CanRequestHandler;

constexpr std::uint32_t kBase = 0x300;
constexpr std::int64_t kMs = 1'000'000;

class RequestHandlerTest : public ::testing::Test {
 protected:
  RequestHandlerTest() {
    EXPECT_EQ(comp_.publish(0, cmmcomp::test::example_model(), cmmcomp::test::kExampleModelId),
              Status::kOk);
  }

  RequestFrames request(std::uint32_t sequence) {
    compensation::MoveRequest m = cmmcomp::test::example_move();
    m.sequence = sequence;
    RequestFrames f;
    EXPECT_EQ(encode_request(m, kBase, f), Status::kOk);
    return f;
  }

  /// Feeds `f` at time `t_ms`; returns what the handler sends.
  std::vector<Frame> feed(const Frame& f, std::int64_t t_ms) {
    CanFrameBatch out;
    handler_.on_frame(f, t_ms * kMs, out);
    return {out.frames.begin(), out.frames.begin() + static_cast<std::ptrdiff_t>(out.size)};
  }

  static RejectInfo reject_of(const std::vector<Frame>& out, std::size_t i = 0) {
    RejectInfo r;
    EXPECT_GT(out.size(), i);
    if (out.size() > i) {
      EXPECT_TRUE(decode_reject(out[i], kBase, r)) << cmmcomp::test::to_text(out[i]);
    }
    return r;
  }

  static bool is_response(const std::vector<Frame>& out, std::uint32_t sequence) {
    DecodedResponse d;
    return out.size() == 3 && decode_response({out[0], out[1], out[2]}, kBase, d) &&
           d.correction.sequence == sequence;
  }

  compensation::MoveCompensator comp_;
  CanRequestHandler handler_{comp_, kBase, std::chrono::milliseconds(50)};
};

TEST_F(RequestHandlerTest, ThreePartsInOrderGetTheResponse) {
  const RequestFrames f = request(7);
  EXPECT_TRUE(feed(f[0], 0).empty());
  EXPECT_TRUE(handler_.assembling());
  EXPECT_TRUE(feed(f[1], 10).empty());
  const std::vector<Frame> out = feed(f[2], 20);
  EXPECT_TRUE(is_response(out, 7));
  EXPECT_FALSE(handler_.assembling());
  const CanCounters c = handler_.counters();
  EXPECT_EQ(c.frames_in, 3u);
  EXPECT_EQ(c.requests, 1u);
  EXPECT_EQ(c.answered, 1u);
  EXPECT_EQ(c.rejected, 0u);
}

TEST_F(RequestHandlerTest, WrongDlcIsRejectedAndAbandonsItsRequest) {
  const RequestFrames f = request(9);
  feed(f[0], 0);
  Frame shortened = f[1];
  shortened.dlc = 7;
  RejectInfo r = reject_of(feed(shortened, 1));
  EXPECT_EQ(r.reason, RejectReason::kWrongDlc);
  EXPECT_EQ(r.sequence, 9);
  EXPECT_EQ(r.part, 1);
  EXPECT_FALSE(handler_.assembling());
  // The rest of that request cannot produce an answer: part 2 is now a missing-part reject.
  r = reject_of(feed(f[2], 2));
  EXPECT_EQ(r.reason, RejectReason::kMissingPart);
  // An empty frame carries no sequence.
  Frame empty;
  empty.id = kBase;
  r = reject_of(feed(empty, 3));
  EXPECT_EQ(r.reason, RejectReason::kWrongDlc);
  EXPECT_EQ(r.sequence, kUnknown);
  EXPECT_EQ(r.part, kUnknown);
  EXPECT_EQ(handler_.counters().malformed, 3u);
  EXPECT_EQ(handler_.counters().answered, 0u);
}

TEST_F(RequestHandlerTest, UnknownMultiplexerValueIsRejected) {
  Frame f = request(3)[0];
  f.data[0] = static_cast<std::uint8_t>(f.data[0] | 0x3);  // part 3
  const RejectInfo r = reject_of(feed(f, 0));
  EXPECT_EQ(r.reason, RejectReason::kUnknownPart);
  EXPECT_EQ(r.sequence, 3);
  EXPECT_EQ(r.part, 3);
  EXPECT_EQ(r.rejected, 1);
}

TEST_F(RequestHandlerTest, StaleSequenceIsRejectedAndTheCurrentRequestGoesOn) {
  const RequestFrames now = request(12);
  const RequestFrames old = request(11);
  feed(now[0], 0);
  const RejectInfo r = reject_of(feed(old[1], 1));  // a part of the previous request
  EXPECT_EQ(r.reason, RejectReason::kSequenceMismatch);
  EXPECT_EQ(r.sequence, 11);
  EXPECT_TRUE(handler_.assembling());
  feed(now[1], 2);
  EXPECT_TRUE(is_response(feed(now[2], 3), 12));
}

TEST_F(RequestHandlerTest, PartWithoutItsPredecessorIsRejected) {
  const RequestFrames f = request(20);
  RejectInfo r = reject_of(feed(f[2], 0));  // nothing being assembled
  EXPECT_EQ(r.reason, RejectReason::kMissingPart);
  EXPECT_EQ(r.part, 2);
  feed(f[0], 1);
  r = reject_of(feed(f[2], 2));  // part 1 skipped
  EXPECT_EQ(r.reason, RejectReason::kMissingPart);
  EXPECT_FALSE(handler_.assembling());
  feed(f[0], 3);
  feed(f[1], 4);
  r = reject_of(feed(f[1], 5));  // duplicate
  EXPECT_EQ(r.reason, RejectReason::kMissingPart);
  EXPECT_EQ(handler_.counters().answered, 0u);
}

TEST_F(RequestHandlerTest, TimeoutBetweenPartsIsRejectedOnceAndNeverAnswered) {
  const RequestFrames f = request(30);
  feed(f[0], 0);
  CanFrameBatch out;
  handler_.on_time(49 * kMs, out);
  EXPECT_EQ(out.size, 0u);
  handler_.on_time(50 * kMs, out);
  ASSERT_EQ(out.size, 1u);
  RejectInfo r;
  ASSERT_TRUE(decode_reject(out.frames[0], kBase, r));
  EXPECT_EQ(r.reason, RejectReason::kTimeout);
  EXPECT_EQ(r.sequence, 30);
  EXPECT_EQ(r.part, 1);  // the part that did not come
  out.size = 0;
  handler_.on_time(60 * kMs, out);
  EXPECT_EQ(out.size, 0u);  // once
  // The late parts find no request: rejects, never an answer with the old part 0.
  EXPECT_EQ(reject_of(feed(f[1], 61)).reason, RejectReason::kMissingPart);
  EXPECT_EQ(reject_of(feed(f[2], 62)).reason, RejectReason::kMissingPart);
  EXPECT_EQ(handler_.counters().timeouts, 1u);
  EXPECT_EQ(handler_.counters().answered, 0u);
}

TEST_F(RequestHandlerTest, LatePartExpiresTheRequestEvenWithoutATick) {
  const RequestFrames f = request(31);
  feed(f[0], 0);
  feed(f[1], 40);  // in time: the deadline moves to 90 ms
  const std::vector<Frame> out = feed(f[2], 95);
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(reject_of(out, 0).reason, RejectReason::kTimeout);
  EXPECT_EQ(reject_of(out, 0).part, 2);
  EXPECT_EQ(reject_of(out, 1).reason, RejectReason::kMissingPart);
}

// Issue 16 D8: near the end of int64 the deadline used to wrap into the past, so a request on
// time was rejected as timed out (and the addition was undefined behaviour).
TEST_F(RequestHandlerTest, ClockNearTheEndOfInt64StillAnswers) {
  const RequestFrames f = request(32);
  const std::int64_t end = std::numeric_limits<std::int64_t>::max();
  CanFrameBatch out;
  handler_.on_frame(f[0], end - 3, out);
  handler_.on_frame(f[1], end - 2, out);
  EXPECT_EQ(out.size, 0u);
  EXPECT_EQ(handler_.deadline_ns(), end);  // saturated
  handler_.on_frame(f[2], end - 1, out);
  EXPECT_TRUE(is_response({out.frames.begin(), out.frames.begin() + 3}, 32));
  EXPECT_EQ(handler_.counters().timeouts, 0u);
}

TEST_F(RequestHandlerTest, NewRequestSupersedesAnIncompleteOne) {
  const RequestFrames a = request(40);
  const RequestFrames b = request(41);
  feed(a[0], 0);
  feed(a[1], 1);
  const RejectInfo r = reject_of(feed(b[0], 2));
  EXPECT_EQ(r.reason, RejectReason::kIncomplete);
  EXPECT_EQ(r.sequence, 40);
  EXPECT_EQ(r.part, 2);
  feed(b[1], 3);
  EXPECT_TRUE(is_response(feed(b[2], 4), 41));
  EXPECT_EQ(handler_.counters().incomplete, 1u);
}

TEST_F(RequestHandlerTest, FieldOutOfRangeNamesTheField) {
  RequestFrames f = request(50);
  std::uint64_t w = load_word(f[1]);
  put_raw(w, request::kAa, 4001);  // above 4000 mm/s²
  store_word(w, f[1]);
  feed(f[0], 0);
  feed(f[1], 1);
  const RejectInfo r = reject_of(feed(f[2], 2));
  EXPECT_EQ(r.reason, RejectReason::kFieldOutOfRange);
  EXPECT_EQ(r.detail, static_cast<std::uint8_t>(RequestField::kAa));
  EXPECT_EQ(r.part, 1);
  EXPECT_EQ(handler_.counters().out_of_range, 1u);
}

TEST_F(RequestHandlerTest, CompensatorRefusalsAreRejectsWithTheStatus) {
  compensation::MoveRequest m = cmmcomp::test::example_move();
  m.axis = 2;  // no model there
  RequestFrames f;
  ASSERT_EQ(encode_request(m, kBase, f), Status::kOk);
  feed(f[0], 0);
  feed(f[1], 1);
  const RejectInfo r = reject_of(feed(f[2], 2));
  EXPECT_EQ(r.reason, RejectReason::kNoModel);
  EXPECT_EQ(r.status, static_cast<std::int16_t>(Status::kNoModel));
  EXPECT_EQ(handler_.counters().refused, 1u);
}

TEST_F(RequestHandlerTest, ResultThatDoesNotFitIsRejectedNotWrapped) {
  ASSERT_EQ(comp_.publish(1, cmmcomp::test::linear_model({400.0, 0, 0, 0}, {0, 0, 0, 0}), 9),
            Status::kOk);
  compensation::MoveRequest m = cmmcomp::test::example_move();
  m.axis = 1;
  RequestFrames f;
  ASSERT_EQ(encode_request(m, kBase, f), Status::kOk);
  feed(f[0], 0);
  feed(f[1], 1);
  const RejectInfo r = reject_of(feed(f[2], 2));
  EXPECT_EQ(r.reason, RejectReason::kResultOutOfRange);
  EXPECT_EQ(r.detail, static_cast<std::uint8_t>(ResponseField::kMpe));
}

// ---- Protocol version 2: WantInterval and response part 3 ----------------------------------

/// The frames `handler` sends for request `f` (three parts, 1 ms apart from `t_ms`).
std::vector<Frame> answer(CanRequestHandler& handler, const RequestFrames& f, std::int64_t t_ms) {
  CanFrameBatch out;
  for (const Frame& x : f) handler.on_frame(x, (t_ms++) * kMs, out);
  return {out.frames.begin(), out.frames.begin() + static_cast<std::ptrdiff_t>(out.size)};
}

RequestFrames interval_request(const compensation::MoveRequest& m) {
  RequestFrames f;
  EXPECT_EQ(encode_request(m, kBase, f, nullptr, /*want_interval=*/true), Status::kOk);
  return f;
}

// A version-1 request (bit 60 clear) gets the three frames it always got, byte for byte, even
// from a calibrated model; the same request with WantInterval gets those three frames and part 3
// with the compensator's own U95, quantised to 0.02 µm.
TEST(CanRequestHandlerInterval, WantIntervalAddsPart3WithTheCompensatorsU95) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(cmmcomp::test::publish_example(comp), Status::kOk);
  CanRequestHandler handler(comp, kBase, std::chrono::milliseconds(50));
  compensation::MoveRequest m = cmmcomp::test::example_move();
  m.pv_mm_s = 84.0;  // outside the training range of PV (5-80 mm/s), not far: the interval grows
  m.sequence = 11;
  RequestFrames v1;
  ASSERT_EQ(encode_request(m, kBase, v1), Status::kOk);
  const std::vector<Frame> old = answer(handler, v1, 0);
  ASSERT_EQ(old.size(), kResponseParts);
  const std::vector<Frame> got = answer(handler, interval_request(m), 10);
  ASSERT_EQ(got.size(), kResponseParts + 1u);
  for (std::size_t p = 0; p < kResponseParts; ++p) {
    EXPECT_EQ(cmmcomp::test::to_text(got[p]), cmmcomp::test::to_text(old[p])) << p;
  }
  compensation::Correction expected;
  ASSERT_TRUE(ok(comp.before_approach(m, expected)));
  ASSERT_EQ(expected.flags & compensation::kFlagNoUncertainty, 0u);
  DecodedResponse d;
  ASSERT_TRUE(decode_response({got[0], got[1], got[2]}, kBase, d));
  ASSERT_TRUE(decode_interval(got[3], kBase, d));
  EXPECT_EQ(d.interval_flags, 0);
  EXPECT_EQ(d.correction.flags, compensation::kFlagOk | compensation::kFlagOutsideDomain);
  for (std::size_t k = 0; k < 4; ++k) {
    const double quantised = std::round(expected.u95_um[k] / 0.02) * 0.02;
    EXPECT_NEAR(d.correction.u95_um[k], quantised, 1e-9) << k;
    EXPECT_NEAR(d.correction.u95_um[k], expected.u95_um[k], 0.01 + 1e-9) << k;
    EXPECT_GT(d.correction.u95_um[k], cmmcomp::test::example_interval().half_width[k]) << k;
  }
  const CanCounters c = handler.counters();
  EXPECT_EQ(c.requests, 2u);
  EXPECT_EQ(c.answered, 2u);
  EXPECT_EQ(c.intervals, 1u);
  EXPECT_EQ(c.rejected, 0u);
}

// A model without an interval calibration: part 3 says NO_UNCERTAINTY and every U95 is 0.
TEST_F(RequestHandlerTest, ModelWithoutCalibrationSendsNoUncertaintyAndZeros) {
  compensation::MoveRequest m = cmmcomp::test::example_move();
  const std::vector<Frame> got = answer(handler_, interval_request(m), 0);
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(cmmcomp::test::to_text(got[3]), "301#1701000000000000");
  DecodedResponse d;
  ASSERT_TRUE(decode_response({got[0], got[1], got[2]}, kBase, d));
  EXPECT_EQ(d.correction.flags, compensation::kFlagOk);  // parts 0-2: version-1 flags only
  ASSERT_TRUE(decode_interval(got[3], kBase, d));
  EXPECT_EQ(d.interval_flags, response::kIntervalNoUncertainty);
  EXPECT_EQ(d.correction.flags, compensation::kFlagOk | compensation::kFlagNoUncertainty);
  for (const double u : d.correction.u95_um) EXPECT_EQ(u, 0.0);
}

// A U95 too large for its 12 bits is sent as raw 4095 with SATURATED; the answer is still given
// (results out of range are still rejected: ResultThatDoesNotFitIsRejectedNotWrapped).
TEST(CanRequestHandlerInterval, HugeU95SaturatesWithTheFlag) {
  compensation::MoveCompensator comp;
  compensation::IntervalCalibration cal;
  cal.coverage = 0.95;
  cal.half_width = {1.0, 1.0, 1.0, 0.5};
  cal.extrapolation_gain = {2000.0, 0.0, 0.0, 0.0};
  ASSERT_EQ(comp.publish(0, cmmcomp::test::example_model(), cal, 7), Status::kOk);
  CanRequestHandler handler(comp, kBase, std::chrono::milliseconds(50));
  compensation::MoveRequest m = cmmcomp::test::example_move();
  m.pv_mm_s = 87.0;  // 7/75 of a range above PV's: U95 of MPE = 1 · (1 + 2000 · 0.093) µm
  const std::vector<Frame> got = answer(handler, interval_request(m), 0);
  ASSERT_EQ(got.size(), 4u);
  DecodedResponse d;
  ASSERT_TRUE(decode_response({got[0], got[1], got[2]}, kBase, d));
  ASSERT_TRUE(decode_interval(got[3], kBase, d));
  EXPECT_EQ(d.interval_flags, response::kIntervalSaturated);
  EXPECT_EQ(get_raw(load_word(got[3]), response::kU95Mpe), 4095);
  EXPECT_NEAR(d.correction.u95_um[0], 81.9, 1e-9);
  EXPECT_NEAR(d.correction.u95_um[1], 1.0, 1e-9);
  EXPECT_NEAR(d.correction.u95_um[3], 0.5, 1e-9);
  EXPECT_EQ(handler.counters().answered, 1u);
  EXPECT_EQ(handler.counters().out_of_range, 0u);
  EXPECT_EQ(handler.counters().outside_domain, 1u);
}

// A move far outside the model's domain is refused under every policy (docs/compensator.md,
// "Domain"): a reject frame with reason OUTSIDE_DOMAIN, counted, and pushed to the outcome log
// with the move; an outside-domain answer is pushed too.
TEST(CanRequestHandlerDomain, FarOutsideIsRefusedCountedAndLogged) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(cmmcomp::test::publish_example(comp), Status::kOk);
  compensation::ServerOutcomeLog log;
  CanRequestHandler handler(comp, kBase, std::chrono::milliseconds(50));
  handler.set_outcome_log(&log);
  compensation::MoveRequest m = cmmcomp::test::example_move();
  m.pv_mm_s = 1000.0;
  m.sequence = 5;
  RequestFrames v1;
  ASSERT_EQ(encode_request(m, kBase, v1), Status::kOk);
  const std::vector<Frame> got = answer(handler, v1, 0);
  ASSERT_EQ(got.size(), 1u);
  RejectInfo r;
  ASSERT_TRUE(decode_reject(got[0], kBase, r));
  EXPECT_EQ(r.reason, RejectReason::kOutsideDomain);
  EXPECT_EQ(r.status, static_cast<std::int16_t>(Status::kOutsideDomainRejected));
  m.pv_mm_s = 84.0;
  m.sequence = 6;
  ASSERT_EQ(encode_request(m, kBase, v1), Status::kOk);
  EXPECT_EQ(answer(handler, v1, 10).size(), kResponseParts);
  const CanCounters c = handler.counters();
  EXPECT_EQ(c.refused, 1u);
  EXPECT_EQ(c.outside_domain, 1u);
  compensation::OutcomeEvent e;
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.status, Status::kOutsideDomainRejected);
  EXPECT_NEAR(e.move.pv_mm_s, 1000.0, 0.1);
  EXPECT_EQ(e.move.sequence, 5u);
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.status, Status::kOutsideDomain);
  EXPECT_FALSE(log.pop(e));
}

// Bits 61-63 of part 0 (and 60-63 of part 2) are still reserved: reason 8, with or without
// WantInterval.
TEST_F(RequestHandlerTest, ReservedBitsNextToWantIntervalStillReject) {
  for (int bit = 61; bit < 64; ++bit) {
    RequestFrames f = interval_request(cmmcomp::test::example_move());
    f[0].data[7] = static_cast<std::uint8_t>(f[0].data[7] | (1u << (bit - 56)));
    const std::vector<Frame> got = answer(handler_, f, bit * 10);
    ASSERT_EQ(got.size(), 1u) << bit;
    const RejectInfo r = reject_of(got);
    EXPECT_EQ(r.reason, RejectReason::kReservedBits) << bit;
    EXPECT_EQ(r.part, 0) << bit;
    EXPECT_EQ(r.sequence, 5) << bit;
  }
  EXPECT_EQ(handler_.counters().intervals, 0u);
  EXPECT_EQ(handler_.counters().answered, 0u);
}

TEST_F(RequestHandlerTest, OtherIdentifiersAreIgnored) {
  Frame other = request(1)[0];
  other.id = kBase + kResponseOffset;
  EXPECT_TRUE(feed(other, 0).empty());
  other.id = 0x123;
  EXPECT_TRUE(feed(other, 0).empty());
  EXPECT_EQ(handler_.counters().ignored, 2u);
  EXPECT_EQ(handler_.counters().frames_in, 0u);
}

TEST_F(RequestHandlerTest, HeartbeatCarriesCountersAndModelIds) {
  const RequestFrames f = request(2);
  for (const Frame& x : f) feed(x, 0);
  const HeartbeatInfo h = handler_.next_heartbeat();
  EXPECT_EQ(h.tick, 0);
  EXPECT_EQ(h.requests, 1);
  EXPECT_EQ(h.answered, 1);
  EXPECT_EQ(h.model_mask, 0b0001);
  EXPECT_EQ(h.model_ids[0], cmmcomp::test::kExampleModelId);
  EXPECT_EQ(h.protocol_version, 2);
  EXPECT_EQ(load_word(encode_heartbeat(h, 0, kBase)) >> 60, 2u);
  EXPECT_EQ(handler_.next_heartbeat().tick, 1);
}

// Every byte pattern on the request identifier, any DLC: never a crash, never more frames out
// than the batch holds, and a response only for a complete request.
TEST_F(RequestHandlerTest, RandomFramesNeverCrashOrOverflow) {
  std::uint64_t x = 0x9E3779B97F4A7C15u;
  const auto next = [&x] {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return x;
  };
  for (int n = 0; n < 100000; ++n) {
    Frame f;
    f.id = kBase;
    f.dlc = static_cast<std::uint8_t>(next() % 9);
    const std::uint64_t w = next();
    for (std::size_t i = 0; i < f.dlc; ++i) f.data[i] = static_cast<std::uint8_t>(w >> (8 * i));
    CanFrameBatch out;
    handler_.on_frame(f, n * kMs / 10, out);
    ASSERT_LE(out.size, CanFrameBatch::kCapacity);
  }
  const CanCounters c = handler_.counters();
  EXPECT_EQ(c.frames_in, 100000u);
}

}  // namespace
