// SPDX-License-Identifier: MIT
/// @file The codec without a kernel: bit packing, round trips of every frame, range rejection.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstring>
#include <limits>
#include <random>
#include <set>
#include <string>

#include "can_test_frames.hpp"
#include "support/test_seed.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins::can;
using compensation::Correction;
using compensation::MoveRequest;

std::array<std::uint64_t, kRequestParts> words_of(const RequestFrames& f) {
  return {load_word(f[0]), load_word(f[1]), load_word(f[2])};
}

TEST(CanCodec, IntelBitPackingMatchesTheDbcConvention) {
  // start|length@1: LSB at `start`, counting bits of byte 0 first.
  std::uint64_t w = 0;
  put_raw(w, request::kAa, 0xABC);  // 36|12: bits 4..7 of byte 4, all of byte 5
  Frame f;
  store_word(w, f);
  EXPECT_EQ(f.data[4], 0xC0);
  EXPECT_EQ(f.data[5], 0xAB);
  EXPECT_EQ(get_raw(load_word(f), request::kAa), 0xABC);
  put_raw(w, request::kDirX, -1);  // signed 12 bits: sign-extended on the way back
  EXPECT_EQ(get_raw(w, request::kDirX), -1);
  EXPECT_EQ(get_raw(w, request::kAa), 0xABC);  // neighbours untouched
}

TEST(CanCodec, SignalsOfOnePartDoNotOverlapAndFitTheFrame) {
  for (const MessageSpec& m : kMessages) {
    for (int mux = -1; mux < 5; ++mux) {
      std::uint64_t used = 0;
      for (std::size_t i = 0; i < m.signal_count; ++i) {
        const SignalSpec& s = m.signals[i];
        if (s.mux >= 0 && s.mux != mux) continue;
        ASSERT_LE(s.start + s.length, 64) << m.name << "." << s.name;
        const std::uint64_t bits = field_mask(s) << s.start;
        EXPECT_EQ(used & bits, 0u) << m.name << "." << s.name << " overlaps in part " << mux;
        used |= bits;
        // The stated range fits the raw field (so a value in range can never wrap).
        const std::int64_t lo = s.is_signed ? -(std::int64_t{1} << (s.length - 1)) : 0;
        const std::int64_t hi = s.is_signed ? (std::int64_t{1} << (s.length - 1)) - 1
                                            : static_cast<std::int64_t>(field_mask(s));
        EXPECT_GE(s.raw_min(), lo) << s.name;
        EXPECT_LE(s.raw_max(), hi) << s.name;
      }
    }
  }
}

// The binding table is the one list of the request's fields: every signal of the request but
// the multiplexor, the sequence and WantInterval once, every RequestField of a signal once, each
// accessor reading and writing its own member.
TEST(CanCodec, TheRequestBindingsNameEveryFieldOnce) {
  std::set<std::string> signals;
  std::set<int> fields;
  for (const RequestBinding& b : kRequestBindings) {
    EXPECT_TRUE(signals.insert(b.spec->name).second) << b.spec->name;
    EXPECT_TRUE(fields.insert(static_cast<int>(b.field)).second) << b.spec->name;
    compensation::MoveRequest m;
    b.set(m, 1.0);
    EXPECT_EQ(b.get(m), 1.0) << b.spec->name;
    compensation::MoveRequest other;
    b.set(other, 0.0);
    EXPECT_NE(std::memcmp(&m, &other, sizeof m), 0) << b.spec->name << " writes no member";
  }
  for (const SignalSpec& s : request::kSignals) {
    const bool framing = &s == &request::kSignals[0] || std::string(s.name) == "ReqSequence" ||
                         std::string(s.name) == "WantInterval";
    EXPECT_EQ(signals.count(s.name), framing ? 0u : 1u) << s.name;
  }
  EXPECT_EQ(fields.size(), request::kSignals.size() - 3);
  EXPECT_EQ(reject_reason(Status::kNoModel), RejectReason::kNoModel);
  EXPECT_EQ(reject_reason(Status::kOutsideDomainRejected), RejectReason::kOutsideDomain);
  EXPECT_EQ(reject_reason(Status::kInvalidInput), RejectReason::kInvalidMove);
}

TEST(CanCodec, RequestRoundTripKeepsEveryFieldWithinResolution) {
  SCOPED_TRACE(cmmcomp::test::seed_message());
  std::mt19937_64 rng(cmmcomp::test::seed());
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const int count = cmmcomp::test::soak_count(2000);
  for (int n = 0; n < count; ++n) {
    MoveRequest m;
    m.sequence = static_cast<std::uint32_t>(n % 64);
    m.axis = static_cast<std::uint8_t>(n % 4);
    m.pv_mm_s = 0.1 + u(rng) * 5999.9;
    m.pd_mm = 0.01 + u(rng) * 599.99;
    m.av_mm_s = 0.01 + u(rng) * 599.99;
    m.ad_mm = 0.001 + u(rng) * 59.999;
    m.pa_mm_s2 = 5 + u(rng) * 19995;
    m.aa_mm_s2 = 1 + u(rng) * 3999;
    m.y_mm = -3000 + u(rng) * 6000;
    m.z_mm = -3000 + u(rng) * 6000;
    const double a = u(rng) * 6.283185307179586;
    const double b = (u(rng) - 0.5) * 3.141592653589793;
    m.direction = {std::cos(a) * std::cos(b), std::sin(a) * std::cos(b), std::sin(b)};
    RequestFrames frames;
    ASSERT_EQ(encode_request(m, 0x300, frames), Status::kOk) << n;
    for (std::size_t p = 0; p < kRequestParts; ++p) {
      EXPECT_EQ(frames[p].id, 0x300u);
      EXPECT_EQ(frames[p].dlc, 8);
      EXPECT_EQ(get_raw(load_word(frames[p]), request::kPart), static_cast<std::int64_t>(p));
    }
    MoveRequest back;
    const RequestCheck check =
        decode_request(words_of(frames), static_cast<std::uint8_t>(m.sequence), back);
    ASSERT_EQ(check.reason, RejectReason::kNone) << n << " field " << int(check.field);
    EXPECT_EQ(back.sequence, m.sequence);
    EXPECT_EQ(back.axis, m.axis);
    EXPECT_NEAR(back.pv_mm_s, m.pv_mm_s, 0.05 + 1e-9);
    EXPECT_NEAR(back.pd_mm, m.pd_mm, 0.005 + 1e-9);
    EXPECT_NEAR(back.av_mm_s, m.av_mm_s, 0.005 + 1e-9);
    EXPECT_NEAR(back.ad_mm, m.ad_mm, 0.0005 + 1e-9);
    EXPECT_NEAR(back.pa_mm_s2, m.pa_mm_s2, 2.5 + 1e-9);
    EXPECT_NEAR(back.aa_mm_s2, m.aa_mm_s2, 0.5 + 1e-9);
    EXPECT_NEAR(back.y_mm, m.y_mm, 0.05 + 1e-9);
    EXPECT_NEAR(back.z_mm, m.z_mm, 0.05 + 1e-9);
    double norm2 = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_NEAR(back.direction[k], m.direction[k], 2e-3);
      norm2 += back.direction[k] * back.direction[k];
    }
    EXPECT_NEAR(norm2, 1.0, 1e-12);  // normalised: what validate_move wants
    EXPECT_EQ(compensation::validate_move(back), Status::kOk);
  }
}

TEST(CanCodec, RequestOutOfRangeIsRejectedNotWrapped) {
  struct Case {
    void (*edit)(MoveRequest&);
    RequestField field;
  };
  const Case cases[] = {
      {[](MoveRequest& m) { m.pv_mm_s = 6000.06; }, RequestField::kPv},
      {[](MoveRequest& m) { m.pv_mm_s = 0.04; }, RequestField::kPv},  // rounds to raw 0
      {[](MoveRequest& m) { m.pv_mm_s = std::numeric_limits<double>::quiet_NaN(); },
       RequestField::kPv},
      {[](MoveRequest& m) { m.pd_mm = 655.36; }, RequestField::kPd},  // would wrap to 0 in 16 bits
      {[](MoveRequest& m) { m.av_mm_s = -1; }, RequestField::kAv},
      {[](MoveRequest& m) { m.axis = 4; }, RequestField::kAxis},
      {[](MoveRequest& m) { m.ad_mm = 60.001; }, RequestField::kAd},
      {[](MoveRequest& m) { m.pa_mm_s2 = 20005; }, RequestField::kPa},
      {[](MoveRequest& m) { m.aa_mm_s2 = std::numeric_limits<double>::infinity(); },
       RequestField::kAa},
      {[](MoveRequest& m) { m.y_mm = 3000.1; }, RequestField::kY},
      {[](MoveRequest& m) { m.z_mm = -3276.9; }, RequestField::kZ},
      {[](MoveRequest& m) { m.direction[0] = -1.001; }, RequestField::kDirX},
      {[](MoveRequest& m) { m.sequence = 64; }, RequestField::kSequence},
  };
  for (const Case& c : cases) {
    MoveRequest m = cmmcomp::test::example_move();
    c.edit(m);
    RequestFrames frames;
    RequestField bad = RequestField::kNone;
    EXPECT_EQ(encode_request(m, 0x300, frames, &bad), Status::kInvalidInput);
    EXPECT_EQ(bad, c.field);
  }
}

TEST(CanCodec, DecodeRejectsRawValuesOutsideTheStatedRange) {
  RequestFrames frames;
  ASSERT_EQ(encode_request(cmmcomp::test::example_move(), 0x300, frames), Status::kOk);
  const auto with = [&](std::size_t part, const SignalSpec& s, std::int64_t raw) {
    auto w = words_of(frames);
    put_raw(w[part], s, raw);
    MoveRequest out;
    out.pv_mm_s = -7;  // must stay untouched on rejection
    const RequestCheck c = decode_request(w, 5, out);
    EXPECT_EQ(out.pv_mm_s, -7);
    return c;
  };
  EXPECT_EQ(with(0, request::kPv, 0).field, RequestField::kPv);      // 0 mm/s: not > 0
  EXPECT_EQ(with(0, request::kPv, 60001).field, RequestField::kPv);  // above 6000 mm/s
  EXPECT_EQ(with(0, request::kAxis, 9).field, RequestField::kAxis);
  EXPECT_EQ(with(1, request::kPa, 4001).field, RequestField::kPa);
  EXPECT_EQ(with(1, request::kY, -30001).field, RequestField::kY);
  EXPECT_EQ(with(2, request::kDirY, 2047).field, RequestField::kDirY);
  const RequestCheck r = with(2, request::kDirY, 1000);  // d = (−1, 0.5, 0): |d| = 1.118
  EXPECT_EQ(r.reason, RejectReason::kFieldOutOfRange);
  EXPECT_EQ(r.field, RequestField::kDirection);
  auto w = words_of(frames);
  w[2] |= request::kReservedMask[2];
  MoveRequest out;
  EXPECT_EQ(decode_request(w, 5, out).reason, RejectReason::kReservedBits);
}

// Version 2: bit 60 of part 0 is WantInterval; bits 61–63 of part 0 and 60–63 of part 2 stay
// reserved (reason 8, the part named).
TEST(CanCodec, WantIntervalIsBit60AndTheOtherReservedBitsStillReject) {
  RequestFrames plain;
  RequestFrames asking;
  ASSERT_EQ(encode_request(cmmcomp::test::example_move(), 0x300, plain), Status::kOk);
  ASSERT_EQ(encode_request(cmmcomp::test::example_move(), 0x300, asking, nullptr, true),
            Status::kOk);
  EXPECT_EQ(load_word(asking[0]), load_word(plain[0]) | (std::uint64_t{1} << 60));
  EXPECT_EQ(load_word(asking[1]), load_word(plain[1]));
  EXPECT_EQ(load_word(asking[2]), load_word(plain[2]));
  MoveRequest out;
  RequestCheck c = decode_request(words_of(plain), 5, out);
  EXPECT_EQ(c.reason, RejectReason::kNone);
  EXPECT_FALSE(c.want_interval);
  c = decode_request(words_of(asking), 5, out);
  EXPECT_EQ(c.reason, RejectReason::kNone);
  EXPECT_TRUE(c.want_interval);
  EXPECT_EQ(request::kReservedMask[0], 0xE000000000000000u);
  for (int bit = 61; bit < 64; ++bit) {
    auto w = words_of(asking);
    w[0] |= std::uint64_t{1} << bit;
    c = decode_request(w, 5, out);
    EXPECT_EQ(c.reason, RejectReason::kReservedBits) << bit;
    EXPECT_EQ(c.part, 0) << bit;
  }
  for (int bit = 60; bit < 64; ++bit) {
    auto w = words_of(plain);
    w[2] |= std::uint64_t{1} << bit;
    c = decode_request(w, 5, out);
    EXPECT_EQ(c.reason, RejectReason::kReservedBits) << bit;
    EXPECT_EQ(c.part, 2) << bit;
  }
}

TEST(CanCodec, ResponseRoundTripAndOutOfRangeResult) {
  Correction c;
  c.mpe_um = 12.345;
  c.rpe_um = -3.21;
  c.mae_um = 327.67;
  c.rae_um = -327.67;
  c.correction_um = {0.0, -1.5, 2.25};
  c.flags = compensation::kFlagOk | compensation::kFlagOutsideDomain;
  c.sequence = 63;
  c.model_id = 0x1234'5678'9ABC'DEF0u;
  ResponseFrames frames;
  ASSERT_EQ(encode_response(c, 3, 0x123, frames), Status::kOk);
  DecodedResponse d;
  ASSERT_TRUE(decode_response(frames, 0x123, d));
  EXPECT_EQ(d.axis, 3);
  EXPECT_EQ(d.correction.sequence, 63u);
  EXPECT_EQ(d.correction.flags, 3u);
  EXPECT_EQ(d.correction.model_id, 0x9ABC'DEF0u);  // low 32 bits
  EXPECT_NEAR(d.correction.mpe_um, 12.35, 1e-9);
  EXPECT_NEAR(d.correction.rpe_um, -3.21, 1e-9);
  EXPECT_NEAR(d.correction.mae_um, 327.67, 1e-9);
  EXPECT_NEAR(d.correction.rae_um, -327.67, 1e-9);
  EXPECT_NEAR(d.correction.correction_um[1], -1.5, 1e-9);
  EXPECT_NEAR(d.correction.correction_um[2], 2.25, 1e-9);
  EXPECT_FALSE(decode_response({frames[0], frames[2], frames[1]}, 0x123, d));  // order checked

  ResponseField bad = ResponseField::kNone;
  c.correction_um[2] = 327.68;  // one step beyond: rejected, not wrapped to −327.68
  EXPECT_EQ(encode_response(c, 0, 0x123, frames, &bad), Status::kInvalidInput);
  EXPECT_EQ(bad, ResponseField::kCorrZ);
  c.correction_um[2] = 0.0;
  c.rpe_um = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(encode_response(c, 0, 0x123, frames, &bad), Status::kInvalidInput);
  EXPECT_EQ(bad, ResponseField::kRpe);
}

// Part 3: U95 quantised to 0.02 µm, 12 bits; raw 4095 means "81.89 µm or more" (SATURATED);
// no calibration: NO_UNCERTAINTY and zeros; negative or NaN: rejected, naming the field.
TEST(CanCodec, IntervalPartRoundTripSaturatesAndFlagsNoUncertainty) {
  Correction c;
  c.flags = compensation::kFlagOk;
  c.sequence = 42;
  c.u95_um = {2.7344, 0.0, 81.87, 81.889};
  Frame f;
  ResponseField bad = ResponseField::kNone;
  ASSERT_EQ(encode_interval(c, 0x123, f, &bad), Status::kOk);
  EXPECT_EQ(f.id, 0x124u);
  EXPECT_EQ(f.dlc, kFrameDlc);
  const std::uint64_t w = load_word(f);
  EXPECT_EQ(get_raw(w, response::kPart), 3);
  EXPECT_EQ(get_raw(w, response::kSequence), 42);
  EXPECT_EQ(get_raw(w, response::kIntervalFlags), 0);
  EXPECT_EQ(get_raw(w, response::kU95Mpe), 137);  // 2.7344 / 0.02 = 136.72
  EXPECT_EQ(get_raw(w, response::kU95Rpe), 0);
  EXPECT_EQ(get_raw(w, response::kU95Mae), 4094);  // 81.87 rounds to 81.88: still exact
  EXPECT_EQ(get_raw(w, response::kU95Rae), 4094);  // 81.889 too
  DecodedResponse d;
  d.correction.sequence = 42;
  ASSERT_TRUE(decode_interval(f, 0x123, d));
  EXPECT_TRUE(d.has_interval);
  EXPECT_EQ(d.interval_flags, 0);
  EXPECT_NEAR(d.correction.u95_um[0], 2.74, 1e-12);
  EXPECT_NEAR(d.correction.u95_um[2], 81.88, 1e-9);
  DecodedResponse other;
  other.correction.sequence = 41;
  EXPECT_FALSE(decode_interval(f, 0x123, other));  // another sequence
  EXPECT_FALSE(other.has_interval);

  // Saturation: 81.89 µm and above, inf included, sent as raw 4095 with SATURATED.
  c.u95_um = {81.89, 1e12, std::numeric_limits<double>::infinity(), 0.68};
  ASSERT_EQ(encode_interval(c, 0x123, f), Status::kOk);
  d = DecodedResponse{};
  d.correction.sequence = 42;
  ASSERT_TRUE(decode_interval(f, 0x123, d));
  EXPECT_EQ(d.interval_flags, response::kIntervalSaturated);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_NEAR(d.correction.u95_um[k], 81.9, 1e-9) << k;
  EXPECT_NEAR(d.correction.u95_um[3], 0.68, 1e-12);
  EXPECT_EQ(get_raw(load_word(f), response::kU95Mpe), 4095);

  // No calibration: NO_UNCERTAINTY, every U95 0 whatever the Correction holds.
  c.flags = compensation::kFlagOk | compensation::kFlagNoUncertainty;
  c.u95_um = {5.0, 5.0, 5.0, 5.0};
  ASSERT_EQ(encode_interval(c, 0x123, f), Status::kOk);
  EXPECT_EQ(load_word(f) >> 16, 0u);
  d = DecodedResponse{};
  d.correction.sequence = 42;
  d.correction.flags = compensation::kFlagOk;
  ASSERT_TRUE(decode_interval(f, 0x123, d));
  EXPECT_EQ(d.interval_flags, response::kIntervalNoUncertainty);
  EXPECT_EQ(d.correction.flags, compensation::kFlagOk | compensation::kFlagNoUncertainty);
  for (const double u : d.correction.u95_um) EXPECT_EQ(u, 0.0);

  // Negative or NaN: no frame, the field named (reject reason 12, Detail 8..11).
  c.flags = compensation::kFlagOk;
  c.u95_um = {1.0, 1.0, -0.01, 1.0};
  EXPECT_EQ(encode_interval(c, 0x123, f, &bad), Status::kInvalidInput);
  EXPECT_EQ(bad, ResponseField::kU95Mae);
  c.u95_um = {1.0, 1.0, 1.0, std::numeric_limits<double>::quiet_NaN()};
  EXPECT_EQ(encode_interval(c, 0x123, f, &bad), Status::kInvalidInput);
  EXPECT_EQ(bad, ResponseField::kU95Rae);
  EXPECT_EQ(static_cast<int>(ResponseField::kU95Rae), 11);
  c.u95_um = {1.0, 1.0, 1.0, 1.0};
  c.sequence = 64;
  EXPECT_EQ(encode_interval(c, 0x123, f), Status::kInvalidInput);

  // A response frame of parts 0-2 is not part 3.
  c.sequence = 42;
  ResponseFrames parts;
  ASSERT_EQ(encode_response(c, 0, 0x123, parts), Status::kOk);
  d = DecodedResponse{};
  d.correction.sequence = 42;
  EXPECT_FALSE(decode_interval(parts[2], 0x123, d));
}

TEST(CanCodec, RejectAndHeartbeatRoundTrip) {
  RejectInfo r;
  r.reason = RejectReason::kInvalidMove;
  r.sequence = 17;
  r.part = kUnknown;
  r.detail = 4;
  r.status = -100;
  r.rejected = 65535;
  const Frame f = encode_reject(r, 0x300);
  EXPECT_EQ(f.id, 0x302u);
  RejectInfo back;
  ASSERT_TRUE(decode_reject(f, 0x300, back));
  EXPECT_EQ(back.reason, r.reason);
  EXPECT_EQ(back.sequence, 17);
  EXPECT_EQ(back.part, kUnknown);
  EXPECT_EQ(back.detail, 4);
  EXPECT_EQ(back.status, -100);
  EXPECT_EQ(back.rejected, 65535);

  HeartbeatInfo h;
  h.tick = 31;
  h.requests = 1000;
  h.answered = 990;
  h.rejected = 10;
  h.model_mask = 0b1010;
  h.model_ids = {0, 0xFFFF'FFFF'FFFFu, 0, 0x1234'5678'9ABCu};
  HeartbeatInfo seen;
  for (std::uint8_t page = 0; page < kHeartbeatPages; ++page) {
    const Frame p = encode_heartbeat(h, page, 0x300);
    EXPECT_EQ(p.id, 0x303u);
    EXPECT_EQ(decode_heartbeat(p, 0x300, seen), page);
  }
  EXPECT_EQ(seen.tick, 31);
  EXPECT_EQ(seen.requests, 1000);
  EXPECT_EQ(seen.answered, 990);
  EXPECT_EQ(seen.rejected, 10);
  EXPECT_EQ(seen.model_mask, 0b1010);
  EXPECT_EQ(seen.model_ids, h.model_ids);
  // Version 2 in page 0, bits 60-63; a version-1 server sent 0 there.
  EXPECT_EQ(seen.protocol_version, 2);
  EXPECT_EQ(kProtocolVersion, 2);
  EXPECT_EQ(load_word(encode_heartbeat(h, 0, 0x300)) >> 60, 2u);
  Frame v1 = encode_heartbeat(h, 0, 0x300);
  v1.data[7] &= 0x0F;
  ASSERT_EQ(decode_heartbeat(v1, 0x300, seen), 0);
  EXPECT_EQ(seen.protocol_version, 0);
  EXPECT_EQ(seen.model_mask, 0b1010);
}

}  // namespace
