// SPDX-License-Identifier: MIT
/// @file 100 000 requests against one server with flat memory: resident set size before and
/// after (works under AddressSanitizer too), every answer checked, a rejected request mixed in
/// every 50.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <limits>

#include "modbus_test_support.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;
namespace map = cmmcomp::plugins::modbus;

/// Resident set size [bytes] from /proc/self/statm.
long resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  long size = 0, resident = 0;
  statm >> size >> resident;
  return resident * ::sysconf(_SC_PAGESIZE);
}

/// CMMCOMP_MODBUS_SOAK_REQUESTS raises (or lowers) the count; default 100 000.
int soak_requests() {
  const char* env = std::getenv("CMMCOMP_MODBUS_SOAK_REQUESTS");
  return env != nullptr ? std::atoi(env) : 100000;
}

TEST(ModbusServerSoak, HundredThousandRequestsWithFlatMemory) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, test::example_model(), test::kExampleModelId), Status::kOk);
  test::LoopbackServer server(comp);
  test::Client c = test::connect_client(server.port());
  const int n = soak_requests();

  auto one = [&](int i) {
    compensation::MoveRequest m = test::example_request();
    m.sequence = static_cast<std::uint32_t>(i);
    m.pv_mm_s = 5.0 + 75.0 * (i % 1000) / 1000.0;
    if (i % 50 == 49) {  // a bad one: exception 03, the previous result stays
      m.pd_mm = std::numeric_limits<double>::infinity();
      map::Result r;
      return !test::transact(c.get(), m, r) && errno == EMBXILVAL;
    }
    map::Result r;
    if (!test::transact(c.get(), m, r)) return false;
    const double x = (static_cast<double>(static_cast<float>(m.pv_mm_s)) - 5.0) / 75.0;
    return r.sequence == static_cast<std::uint16_t>(i) && r.flags == compensation::kFlagOk &&
           static_cast<float>(r.rae_um) == static_cast<float>(1.5 + x);
  };

  for (int i = 0; i < 2000; ++i) ASSERT_TRUE(one(i)) << i;  // warm up: buffers, page faults
  const long before = resident_bytes();
  int failures = 0;
  for (int i = 0; i < n; ++i) failures += one(i) ? 0 : 1;
  const long after = resident_bytes();
  EXPECT_EQ(failures, 0);
  RecordProperty("rss_before_bytes", static_cast<int>(before));
  RecordProperty("rss_after_bytes", static_cast<int>(after));
  std::printf("%d requests: RSS %ld kB -> %ld kB\n", n, before / 1024, after / 1024);
  EXPECT_LE(after - before, 512 * 1024) << "resident memory grew by " << (after - before) << " B";
  const ModbusCounters k = server.server().counters();
  EXPECT_EQ(k.requests, static_cast<std::uint64_t>(n + 2000));
  EXPECT_EQ(k.rejected, static_cast<std::uint64_t>((n + 2000) / 50));
  EXPECT_EQ(k.receive_errors, 0u);
}

}  // namespace
