// SPDX-License-Identifier: MIT
/// @file The per-request path allocates nothing: ModbusRequestHandler::handle on every kind of
/// request, and (stronger) a whole loopback TCP transaction through libmodbus, server and
/// client in this process, once connected.
#include <gtest/gtest.h>

#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstdint>
#include <limits>
#include <vector>

#include "modbus_test_support.hpp"
#include "support/allocation_counter.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;
namespace map = cmmcomp::plugins::modbus;

TEST(ModbusRequestHandlerRt, HandleDoesNotAllocate) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, test::example_model(), test::kExampleModelId), Status::kOk);
  ModbusRequestHandler handler(comp, 1, ModbusTransport::kTcp);
  // Requests built before counting: a good write, a NaN write, reads, an illegal address.
  const std::vector<std::uint8_t> write = test::hex(test::kExampleWriteAdu);
  std::vector<std::uint8_t> nan = write;
  nan[7 + 6 + 2 * map::kPv] = 0x7F;
  nan[7 + 6 + 2 * map::kPv + 1] = 0xC0;
  const std::vector<std::uint8_t> read = test::hex(test::kExampleReadAdu);
  const std::uint8_t bad_address[] = {kReadHoldingRegisters, 0, 60, 0, 1};

  std::size_t replies = 0;
  test::AllocationCounter allocations;
  for (int i = 0; i < 10000; ++i) {
    replies +=
        handler.handle(1, write.data() + 7, write.size() - 7).kind == ModbusDecision::Kind::kReply;
    replies +=
        handler.handle(1, nan.data() + 7, nan.size() - 7).kind == ModbusDecision::Kind::kReply;
    replies +=
        handler.handle(1, read.data() + 7, read.size() - 7).kind == ModbusDecision::Kind::kReply;
    replies +=
        handler.handle(1, bad_address, sizeof bad_address).kind == ModbusDecision::Kind::kReply;
  }
  EXPECT_EQ(allocations.count(), 0u);
  EXPECT_EQ(replies, 20000u);
}

TEST(ModbusServerRt, LoopbackTransactionsDoNotAllocateOnceConnected) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, test::example_model(), test::kExampleModelId), Status::kOk);
  test::LoopbackServer server(comp);
  test::Client client = test::connect_client(server.port());
  map::HoldingRegisters h{};
  map::encode_request(test::example_request(), h);
  map::InputRegisters in{};
  // Warm up: the connection is accepted and registered by the server thread.
  ASSERT_EQ(modbus_write_registers(client.get(), 0, map::kRequestCount, h.data()),
            map::kRequestCount);
  ASSERT_TRUE(test::read_inputs(client.get(), in));

  int good = 0;
  {
    test::AllocationCounter allocations;  // counts both threads
    for (int i = 0; i < 2000; ++i) {
      h[map::kSequence] = static_cast<std::uint16_t>(i);
      good += modbus_write_registers(client.get(), 0, map::kRequestCount, h.data()) ==
              map::kRequestCount;
      good += test::read_inputs(client.get(), in);
    }
    EXPECT_EQ(allocations.count(), 0u);
  }
  EXPECT_EQ(good, 4000);
}

}  // namespace
