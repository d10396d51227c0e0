// SPDX-License-Identifier: MIT
/// @file plugins::ModbusTcpAduResponder, the server's frame path in process: the answers a
/// Modbus TCP client would get, byte for byte, without a network.
#include <gtest/gtest.h>

#include <cmmcomp/plugins/modbus_adu_responder.hpp>
#include <cstdint>
#include <vector>

namespace {

using cmmcomp::plugins::ModbusTcpAduResponder;
using Bytes = std::vector<std::uint8_t>;

ModbusTcpAduResponder::Answer respond(ModbusTcpAduResponder& r, const Bytes& adu) {
  return r.respond(adu.data(), adu.size());
}

TEST(ModbusTcpAduResponder, ReadsTheProtocolVersionLikeTheServer) {
  cmmcomp::compensation::MoveCompensator compensator;
  ModbusTcpAduResponder r(compensator);
  // FC04 read input register 0 (protocol version 2), transaction 7.
  const auto a =
      respond(r, {0x00, 0x07, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x00, 0x00, 0x01});
  ASSERT_EQ(a.kind, ModbusTcpAduResponder::Answer::Kind::kAnswered);
  EXPECT_EQ(a.adu, (Bytes{0x00, 0x07, 0x00, 0x00, 0x00, 0x05, 0x01, 0x04, 0x02, 0x00, 0x02}));
  EXPECT_EQ(r.handler().counters().answered, 1u);
}

TEST(ModbusTcpAduResponder, AnswersExceptionsAndTheNextRequestStartsClean) {
  cmmcomp::compensation::MoveCompensator compensator;
  ModbusTcpAduResponder r(compensator);
  // FC03 beyond the 58 holding registers: exception 02.
  auto a = respond(r, {0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x03, 0x00, 0x3A, 0x00, 0x01});
  EXPECT_EQ(a.adu, (Bytes{0x00, 0x01, 0x00, 0x00, 0x00, 0x03, 0x01, 0x83, 0x02}));
  // Another unit id over TCP: exception 0B (gateway target failed).
  a = respond(r, {0x00, 0x02, 0x00, 0x00, 0x00, 0x06, 0x05, 0x03, 0x00, 0x00, 0x00, 0x01});
  EXPECT_EQ(a.adu, (Bytes{0x00, 0x02, 0x00, 0x00, 0x00, 0x03, 0x05, 0x83, 0x0B}));
  // A request shorter than its function code says: the server would drop the connection.
  a = respond(r, {0x00, 0x03, 0x00, 0x00, 0x00, 0x04, 0x01, 0x03, 0x00, 0x00});
  EXPECT_EQ(a.kind, ModbusTcpAduResponder::Answer::Kind::kReceiveError);
  EXPECT_TRUE(a.adu.empty());
  // And the next good request is answered normally.
  a = respond(r, {0x00, 0x04, 0x00, 0x00, 0x00, 0x06, 0x01, 0x04, 0x00, 0x00, 0x00, 0x01});
  EXPECT_EQ(a.adu, (Bytes{0x00, 0x04, 0x00, 0x00, 0x00, 0x05, 0x01, 0x04, 0x02, 0x00, 0x02}));
}

}  // namespace
