// SPDX-License-Identifier: MIT
/// @file ModbusRequestHandler on raw PDUs (no sockets): exceptions, refused writes change
/// nothing, whole results, unit ids, FC23, the status block.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstdint>
#include <limits>
#include <vector>

#include "modbus_test_support.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;
namespace map = cmmcomp::plugins::modbus;
using Kind = ModbusDecision::Kind;

std::vector<std::uint8_t> pdu_write(std::uint16_t address, const std::vector<std::uint16_t>& regs) {
  std::vector<std::uint8_t> p = {kWriteMultipleRegisters,
                                 static_cast<std::uint8_t>(address >> 8),
                                 static_cast<std::uint8_t>(address),
                                 static_cast<std::uint8_t>(regs.size() >> 8),
                                 static_cast<std::uint8_t>(regs.size()),
                                 static_cast<std::uint8_t>(2 * regs.size())};
  for (std::uint16_t r : regs) {
    p.push_back(static_cast<std::uint8_t>(r >> 8));
    p.push_back(static_cast<std::uint8_t>(r));
  }
  return p;
}

std::vector<std::uint8_t> pdu_read(std::uint8_t function, std::uint16_t address, std::uint16_t n) {
  return {function,
          static_cast<std::uint8_t>(address >> 8),
          static_cast<std::uint8_t>(address),
          static_cast<std::uint8_t>(n >> 8),
          static_cast<std::uint8_t>(n)};
}

std::vector<std::uint16_t> request_regs(const compensation::MoveRequest& m) {
  map::HoldingRegisters h{};
  map::encode_request(m, h);
  return {h.begin(), h.begin() + map::kRequestCount};
}

class ModbusRequestHandlerTest : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_EQ(comp_.publish(0, test::example_model(), test::kExampleModelId), Status::kOk);
  }
  ModbusDecision send(const std::vector<std::uint8_t>& pdu, std::uint8_t unit = 1) {
    return handler_.handle(unit, pdu.data(), pdu.size());
  }
  compensation::MoveCompensator comp_;
  ModbusRequestHandler handler_{comp_, 1, ModbusTransport::kTcp};
};

TEST_F(ModbusRequestHandlerTest, WriteWithSequenceComputes) {
  EXPECT_EQ(send(pdu_write(0, request_regs(test::example_request()))).kind, Kind::kReply);
  const map::Result r = map::decode_result(handler_.input());
  EXPECT_EQ(r.sequence, 7);
  EXPECT_EQ(r.rae_um, 2.0);
  EXPECT_EQ(handler_.counters().computations, 1u);
  // The copy in holding registers equals the result block, and the interval copy the interval
  // block (protocol version 2), so one FC23 reading holding 25-57 gets both.
  for (std::size_t i = 0; i < map::kResultWords; ++i) {
    EXPECT_EQ(handler_.holding()[map::kResultCopy + i], handler_.input()[map::kResultSequence + i]);
  }
  for (std::size_t i = 0; i < map::kIntervalWords; ++i) {
    EXPECT_EQ(handler_.holding()[map::kIntervalCopy + i],
              handler_.input()[map::kIntervalFlags + i]);
  }
  EXPECT_EQ(map::kIntervalCopy, map::kResultCopy + map::kResultWords);
  // The example model has no interval calibration: U95 0, flagged as unknown in the new block
  // only.
  EXPECT_EQ(r.interval_flags, compensation::kFlagOk | compensation::kFlagNoUncertainty);
  EXPECT_EQ(r.flags, compensation::kFlagOk);
  for (const double u : r.u95_um) EXPECT_EQ(u, 0.0);
}

TEST_F(ModbusRequestHandlerTest, BlockThenSequenceWriteComputes) {
  std::vector<std::uint16_t> regs = request_regs(test::example_request());
  regs.pop_back();  // without the sequence: staged, nothing computed
  EXPECT_EQ(send(pdu_write(0, regs)).kind, Kind::kReply);
  EXPECT_EQ(handler_.counters().computations, 0u);
  EXPECT_EQ(map::decode_result(handler_.input()).sequence, 0);
  const std::vector<std::uint8_t> seq = {kWriteSingleRegister, 0, map::kSequence, 0, 42};
  EXPECT_EQ(send(seq).kind, Kind::kReply);
  EXPECT_EQ(map::decode_result(handler_.input()).sequence, 42);
  EXPECT_EQ(map::decode_result(handler_.input()).mpe_um, 11.0);
}

TEST_F(ModbusRequestHandlerTest, FloatWrittenOneRegisterAtATime) {
  ASSERT_EQ(send(pdu_write(0, request_regs(test::example_request()))).kind, Kind::kReply);
  // PV 42.5 (0x422A0000) -> 20.0 (0x41A00000): high word, then low word, then the trigger.
  const std::vector<std::uint8_t> high = {kWriteSingleRegister, 0, map::kPv, 0x41, 0xA0};
  const std::vector<std::uint8_t> low = {kWriteSingleRegister, 0, map::kPv + 1, 0x00, 0x00};
  const std::vector<std::uint8_t> seq = {kWriteSingleRegister, 0, map::kSequence, 0, 12};
  EXPECT_EQ(send(high).kind, Kind::kReply);
  EXPECT_EQ(send(low).kind, Kind::kReply);
  EXPECT_EQ(send(seq).kind, Kind::kReply);
  const map::Result r = map::decode_result(handler_.input());
  EXPECT_EQ(r.sequence, 12);
  EXPECT_EQ(r.rae_um, static_cast<double>(1.7f));  // 1.5 + (20 - 5)/75, in binary32
  // A high word that makes the float NaN is refused on its own.
  const std::vector<std::uint8_t> nan_high = {kWriteSingleRegister, 0, map::kPv, 0x7F, 0xC0};
  EXPECT_EQ(send(nan_high).exception, kIllegalDataValue);
  EXPECT_EQ(map::get_f32(&handler_.holding()[map::kPv]), 20.0f);
}

TEST_F(ModbusRequestHandlerTest, IllegalAddressIsException02) {
  const ModbusDecision d = send(pdu_read(kReadHoldingRegisters, map::kHoldingCount - 1, 2));
  EXPECT_EQ(d.kind, Kind::kException);
  EXPECT_EQ(d.exception, kIllegalDataAddress);
  EXPECT_EQ(send(pdu_read(kReadInputRegisters, map::kInputCount, 1)).exception,
            kIllegalDataAddress);
  EXPECT_EQ(send(pdu_write(map::kResultCopy, {1})).exception, kIllegalDataAddress);  // read-only
  EXPECT_EQ(send(pdu_write(map::kSequence, {1, 2})).exception, kIllegalDataAddress);
  EXPECT_EQ(send(pdu_read(0x01, 0, 1)).exception, kIllegalFunction);  // no coils
  EXPECT_EQ(handler_.counters().exceptions, 5u);
  EXPECT_EQ(handler_.counters().rejected, 0u);
}

// Issue 16 D11: an exception answer to 0x90 used to wrap to 0x10, a normal FC16 answer.
TEST_F(ModbusRequestHandlerTest, FunctionCodesFrom0x80AreNotAnswered) {
  for (int fc = 0x80; fc <= 0xFF; ++fc) {
    const std::vector<std::uint8_t> pdu = {static_cast<std::uint8_t>(fc), 0, 0, 0, 1};
    EXPECT_EQ(send(pdu).kind, Kind::kSilent) << fc;
    // Found by fuzz_modbus_adu: for another unit, the 0B exception wrapped the same way.
    EXPECT_EQ(handler_.handle(7, pdu.data(), pdu.size()).kind, Kind::kSilent) << fc;
  }
  EXPECT_EQ(handler_.counters().exceptions, 0u);
  EXPECT_EQ(send(pdu_read(0x7F, 0, 1)).exception, kIllegalFunction);  // the last code answered
}

TEST_F(ModbusRequestHandlerTest, BadQuantityIsException03) {
  EXPECT_EQ(send(pdu_read(kReadInputRegisters, 0, 0)).exception, kIllegalDataValue);
  EXPECT_EQ(send(pdu_read(kReadInputRegisters, 0, 126)).exception, kIllegalDataValue);
  std::vector<std::uint8_t> bad = pdu_write(0, {0, 0});
  bad[5] = 5;  // byte count disagrees with the quantity
  EXPECT_EQ(send(bad).exception, kIllegalDataValue);
}

TEST_F(ModbusRequestHandlerTest, NanIsException03AndChangesNothing) {
  ASSERT_EQ(send(pdu_write(0, request_regs(test::example_request()))).kind, Kind::kReply);
  const map::HoldingRegisters holding = handler_.holding();
  const map::InputRegisters input = handler_.input();
  compensation::MoveRequest m = test::example_request();
  m.sequence = 8;
  m.pv_mm_s = std::numeric_limits<double>::quiet_NaN();
  const ModbusDecision d = send(pdu_write(0, request_regs(m)));
  EXPECT_EQ(d.kind, Kind::kException);
  EXPECT_EQ(d.exception, kIllegalDataValue);
  EXPECT_EQ(handler_.holding(), holding);
  EXPECT_EQ(handler_.input(), input);
  EXPECT_EQ(handler_.counters().rejected, 1u);
}

TEST_F(ModbusRequestHandlerTest, NotUnitDirectionIsRejectedAtTheTrigger) {
  compensation::MoveRequest m = test::example_request();
  m.direction = {0.6, 0.6, 0.0};  // every component in range, |d| ≠ 1
  std::vector<std::uint16_t> regs = request_regs(m);
  regs.pop_back();
  EXPECT_EQ(send(pdu_write(0, regs)).kind, Kind::kReply);  // staged
  const std::vector<std::uint8_t> seq = {kWriteSingleRegister, 0, map::kSequence, 0, 9};
  EXPECT_EQ(send(seq).exception, kIllegalDataValue);
  EXPECT_EQ(handler_.holding()[map::kSequence], 0);  // the trigger write was not applied
  EXPECT_EQ(map::decode_result(handler_.input()).sequence, 0);
}

TEST_F(ModbusRequestHandlerTest, NegativeSpeedIsException03) {
  compensation::MoveRequest m = test::example_request();
  m.av_mm_s = -5.0;
  EXPECT_EQ(send(pdu_write(0, request_regs(m))).exception, kIllegalDataValue);
  const std::vector<std::uint8_t> axis = {kWriteSingleRegister, 0, map::kAxis, 0, 4};
  EXPECT_EQ(send(axis).exception, kIllegalDataValue);
}

TEST_F(ModbusRequestHandlerTest, NoModelIsAStatusNotAnException) {
  compensation::MoveRequest m = test::example_request();
  m.axis = 2;
  m.sequence = 11;
  EXPECT_EQ(send(pdu_write(0, request_regs(m))).kind, Kind::kReply);
  const map::Result r = map::decode_result(handler_.input());
  EXPECT_EQ(r.sequence, 11);
  EXPECT_EQ(r.axis, 2);
  EXPECT_EQ(r.status, static_cast<std::int16_t>(Status::kNoModel));
  EXPECT_EQ(r.flags, compensation::kFlagNoModel);
  EXPECT_EQ(r.rae_um, 0.0);
}

TEST_F(ModbusRequestHandlerTest, OutsideDomainIsFlagged) {
  compensation::MoveRequest m = test::example_request();
  m.pv_mm_s = 84.0;  // training range 5 .. 80: clamped (not far outside: within 7.5)
  compensation::ServerOutcomeLog log;
  handler_.set_outcome_log(&log);
  EXPECT_EQ(send(pdu_write(0, request_regs(m))).kind, Kind::kReply);
  const map::Result r = map::decode_result(handler_.input());
  EXPECT_EQ(r.status, static_cast<std::int16_t>(Status::kOutsideDomain));
  EXPECT_EQ(r.flags, compensation::kFlagOk | compensation::kFlagOutsideDomain);
  EXPECT_EQ(r.mpe_um, 12.0);  // x̂ clamped to 1
  // Far outside: refused under every policy (docs/compensator.md, "Domain"), status in the block.
  m.pv_mm_s = 500.0;
  m.sequence = 2;
  EXPECT_EQ(send(pdu_write(0, request_regs(m))).kind, Kind::kReply);
  const map::Result far = map::decode_result(handler_.input());
  EXPECT_EQ(far.status, static_cast<std::int16_t>(Status::kOutsideDomainRejected));
  EXPECT_EQ(far.flags & compensation::kFlagOk, 0u);
  EXPECT_EQ(handler_.counters().outside_domain, 1u);
  EXPECT_EQ(handler_.counters().refused, 1u);
  compensation::OutcomeEvent e;
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.status, Status::kOutsideDomain);
  ASSERT_TRUE(log.pop(e));
  EXPECT_EQ(e.status, Status::kOutsideDomainRejected);
  EXPECT_EQ(e.move.pv_mm_s, 500.0);
  EXPECT_FALSE(log.pop(e));
}

TEST_F(ModbusRequestHandlerTest, ReadWriteMultipleWritesThenReadsTheResultCopy) {
  std::vector<std::uint8_t> p = {kReadWriteMultipleRegisters,
                                 0,
                                 map::kResultCopy,
                                 0,
                                 map::kResultWords,
                                 0,
                                 0,
                                 0,
                                 map::kRequestCount,
                                 2 * map::kRequestCount};
  for (std::uint16_t r : request_regs(test::example_request())) {
    p.push_back(static_cast<std::uint8_t>(r >> 8));
    p.push_back(static_cast<std::uint8_t>(r));
  }
  EXPECT_EQ(send(p).kind, Kind::kReply);
  EXPECT_EQ(handler_.holding()[map::kResultCopy], 7);  // sequence echo, ready for the read part
}

TEST_F(ModbusRequestHandlerTest, UnitIds) {
  const std::vector<std::uint8_t> read = pdu_read(kReadInputRegisters, 0, 1);
  EXPECT_EQ(send(read, 1).kind, Kind::kReply);
  EXPECT_EQ(send(read, 0xFF).kind, Kind::kReply);
  EXPECT_EQ(send(read, 2).exception, kGatewayTargetFailed);
  ModbusRequestHandler rtu(comp_, 5, ModbusTransport::kRtu);
  EXPECT_EQ(rtu.handle(5, read.data(), read.size()).kind, Kind::kReply);
  EXPECT_EQ(rtu.handle(0, read.data(), read.size()).kind, Kind::kSilent);
  EXPECT_EQ(rtu.handle(6, read.data(), read.size()).kind, Kind::kSilent);
  EXPECT_EQ(rtu.counters().requests, 1u);
}

TEST_F(ModbusRequestHandlerTest, StatusBlockShowsCountersAndModelIds) {
  ASSERT_EQ(comp_.publish(3, test::example_model(), 0xAABBull), Status::kOk);
  send(pdu_write(0, request_regs(test::example_request())));
  send(pdu_read(0x01, 0, 1));  // exception 01
  EXPECT_EQ(send(pdu_read(kReadInputRegisters, 0, map::kInputCount)).kind, Kind::kReply);
  const auto& in = handler_.input();
  EXPECT_EQ(in[map::kProtocolVersionReg], map::kProtocolVersion);
  EXPECT_EQ(map::get_u32(&in[map::kRequests]), 3u);
  EXPECT_EQ(map::get_u32(&in[map::kAnswered]), 1u);
  EXPECT_EQ(map::get_u32(&in[map::kExceptions]), 1u);
  EXPECT_EQ(map::get_u32(&in[map::kComputations]), 1u);
  EXPECT_EQ(map::get_u64(&in[map::kModelIdAxis0]), test::kExampleModelId);
  EXPECT_EQ(map::get_u64(&in[map::kModelIdAxis0 + 12]), 0xAABBull);
  EXPECT_EQ(map::get_u64(&in[map::kModelIdAxis0 + 4]), 0u);
}

TEST_F(ModbusRequestHandlerTest, TruncatedPdusAreRefusedNotRead) {
  const std::uint8_t fc16[] = {kWriteMultipleRegisters, 0, 0, 0, 25, 50, 1, 2};
  for (std::size_t n = 0; n <= sizeof fc16; ++n) {
    EXPECT_EQ(handler_.handle(1, fc16, n).kind, Kind::kException) << n;
  }
  EXPECT_EQ(handler_.handle(1, nullptr, 0).kind, Kind::kException);
}

}  // namespace
