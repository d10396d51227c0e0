// SPDX-License-Identifier: MIT
/// @file cmmcomp-sim serve-ipp as a process: port 0 prints the port it took, a client probes a
/// point through it, SIGINT and SIGTERM end it with status 0, a bad --listen is a usage error.
#include <gtest/gtest.h>
#include <signal.h>

#include <chrono>
#include <cmath>
#include <cmmcomp/ipp/client.hpp>
#include <string>
#include <vector>

#include "agent/agent_process.hpp"

using cmmcomp::test::AgentProcess;
using std::chrono::milliseconds;

namespace {

/// The port from "listening on 127.0.0.1:PORT\n" (0 when not yet printed).
int port_of(const std::string& output) {
  const std::string head = "listening on 127.0.0.1:";
  const std::size_t at = output.find(head);
  if (at == std::string::npos) return 0;
  const std::size_t end = output.find('\n', at);
  if (end == std::string::npos) return 0;
  return std::stoi(output.substr(at + head.size(), end - at - head.size()));
}

}  // namespace

TEST(SimServeIpp, ServesThePortItPrintsAndStopsCleanlyOnEitherSignal) {
  for (int sig : {SIGTERM, SIGINT}) {
    AgentProcess p(CMMCOMP_SIM_PATH,
                   {"serve-ipp", "--listen", "127.0.0.1:0", "--noise", "--seed", "3"});
    ASSERT_TRUE(p.wait_for_output("listening on 127.0.0.1:", milliseconds(20000))) << p.output();
    int port = 0;
    for (int i = 0; i < 200 && port == 0; ++i) {
      p.wait_for_output("\n", milliseconds(100));
      port = port_of(p.output());
    }
    ASSERT_GT(port, 0) << p.output();
    {
      cmmcomp::ipp::Client c("127.0.0.1", static_cast<std::uint16_t>(port));
      EXPECT_TRUE(c.call("StartSession()").ok());
      EXPECT_TRUE(c.call("GoTo(X(20), Y(250), Z(0))").ok());
      const cmmcomp::ipp::Transaction t = c.call("PtMeas(X(0), Y(250), Z(0), IJK(1, 0, 0))");
      ASSERT_TRUE(t.ok());
      ASSERT_EQ(t.data.size(), 1u);
      EXPECT_EQ(t.data[0].rfind("X(", 0), 0u);
      EXPECT_NE(t.data[0], "X(0), Y(250), Z(0)");  // the twin's error and the noise are in it
    }
    p.signal(sig);
    EXPECT_EQ(p.wait_exit(milliseconds(20000)), 0) << p.output();
    EXPECT_NE(p.output().find("stopped"), std::string::npos);
  }
}

TEST(SimServeIpp, ABadListenAddressIsAUsageError) {
  for (const char* bad : {"127.0.0.1", "127.0.0.1:99999", ":80", "127.0.0.1:x"}) {
    AgentProcess p(CMMCOMP_SIM_PATH, {"serve-ipp", "--listen", bad});
    EXPECT_EQ(p.wait_exit(milliseconds(20000)), 2) << bad << ": " << p.output();
  }
  // An address it cannot listen on: a clear message and status 1.
  AgentProcess p(CMMCOMP_SIM_PATH, {"serve-ipp", "--listen", "192.0.2.1:1294"});
  EXPECT_EQ(p.wait_exit(milliseconds(20000)), 1) << p.output();
  EXPECT_NE(p.output().find("cannot listen on 192.0.2.1:1294"), std::string::npos) << p.output();
}

#ifdef CMMCOMP_VC_PATH
namespace {

/// The numbers of "--reversal-map Y=V,Y=V,…" in cmmcomp-vc --map-only's output.
std::vector<double> reversal_map(const std::string& output) {
  std::vector<double> v;
  const std::string head = "--reversal-map ";
  std::size_t at = output.find(head);
  if (at == std::string::npos) return v;
  at += head.size();
  const std::size_t end = output.find_first_of(" \n", at);
  std::string list = output.substr(at, end - at) + ",";
  for (std::size_t pos = 0, comma; (comma = list.find(',', pos)) != std::string::npos;
       pos = comma + 1) {
    const std::string node = list.substr(pos, comma - pos);
    v.push_back(std::stod(node.substr(node.find('=') + 1)));
  }
  return v;
}

}  // namespace

TEST(SimServeIpp, CmmcompVcTakesItsTouchesOverIppAsFromTheTwinInProcess) {
  AgentProcess server(CMMCOMP_SIM_PATH, {"serve-ipp", "--listen", "127.0.0.1:0"});
  int port = 0;
  for (int i = 0; i < 400 && port == 0; ++i) {
    server.wait_for_output("\n", milliseconds(50));
    port = port_of(server.output());
  }
  ASSERT_GT(port, 0) << server.output();
  const std::vector<std::string> args = {
      "--qualify", "--map-only", "--no-noise", "--qualify-touches", "2"};
  std::vector<std::string> over_ipp = args;
  over_ipp.push_back("--ipp");
  over_ipp.push_back("127.0.0.1:" + std::to_string(port));
  AgentProcess remote(CMMCOMP_VC_PATH, over_ipp);
  ASSERT_EQ(remote.wait_exit(milliseconds(60000)), 0) << remote.output();
  AgentProcess local(CMMCOMP_VC_PATH, args);
  ASSERT_EQ(local.wait_exit(milliseconds(60000)), 0) << local.output();
  const std::vector<double> a = reversal_map(remote.output()), b = reversal_map(local.output());
  ASSERT_EQ(a.size(), 3u) << remote.output();
  ASSERT_EQ(b.size(), a.size()) << local.output();
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_NEAR(a[i], b[i], 2e-3);  // the I++ numbers carry 1e-3 um; the map prints 4 decimals
    EXPECT_GT(std::fabs(b[i]), 1e-3);
  }
  server.signal(SIGTERM);
  EXPECT_EQ(server.wait_exit(milliseconds(20000)), 0);
  // No server there: a usage-level failure (status 2), as an unreachable agent.
  AgentProcess gone(CMMCOMP_VC_PATH,
                    {"--qualify", "--map-only", "--ipp", "127.0.0.1:" + std::to_string(port)});
  EXPECT_EQ(gone.wait_exit(milliseconds(60000)), 2) << gone.output();
  EXPECT_NE(gone.output().find("I++ client: cannot connect"), std::string::npos) << gone.output();
}
#endif
