// SPDX-License-Identifier: MIT
/// @file The length test over I++ DME (issue 39 §4): cmmcomp-vc → cmmcomp-agent --ipp-proxy →
/// cmmcomp-sim serve-ipp gives the same per-Y verdicts as cmmcomp-vc with the twin in process and
/// the same model served over Modbus, and so does the vc over I++ without the proxy (touches
/// from the server, corrections from the Modbus agent). No noise: every run sees the same twin.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "tools/agent/agent_process.hpp"

#ifndef CMMCOMP_AGENT_PATH
#error "CMMCOMP_AGENT_PATH must name the cmmcomp-agent executable"
#endif
#ifndef CMMCOMP_VC_PATH
#error "CMMCOMP_VC_PATH must name the cmmcomp-vc executable"
#endif
#ifndef CMMCOMP_SIM_PATH
#error "CMMCOMP_SIM_PATH must name the cmmcomp-sim executable"
#endif

namespace cmmcomp {
namespace {

using namespace std::chrono_literals;
using test::AgentProcess;

nlohmann::json run_vc(const std::vector<std::string>& extra) {
  std::vector<std::string> args = {
      "--lengths", "20,100,400", "--y", "0,250,500", "--repeats", "1", "--no-noise", "--json"};
  args.insert(args.end(), extra.begin(), extra.end());
  AgentProcess vc(CMMCOMP_VC_PATH, args);
  const int status = vc.wait_exit(60s);
  const std::string& out = vc.output();
  EXPECT_EQ(status, 0) << out;
  const auto first = out.find('{');
  const auto last = out.rfind('}');
  if (status != 0 || first == std::string::npos || last == std::string::npos) return {};
  return nlohmann::json::parse(out.substr(first, last - first + 1));
}

TEST(VcIppProxyE2e, SameVerdictsThroughTheProxyAsOverModbus) {
  std::string why;
  test::RunningAgent modbus = test::start_modbus_agent(CMMCOMP_AGENT_PATH, {}, 11, &why);
  ASSERT_TRUE(modbus.process) << why;
  AgentProcess direct_server(CMMCOMP_SIM_PATH, {"serve-ipp", "--listen", "127.0.0.1:0"});
  const int direct_port = direct_server.port_after("listening on 127.0.0.1:");
  ASSERT_GT(direct_port, 0) << direct_server.output();
  AgentProcess proxied_server(CMMCOMP_SIM_PATH, {"serve-ipp", "--listen", "127.0.0.1:0"});
  const int upstream_port = proxied_server.port_after("listening on 127.0.0.1:");
  ASSERT_GT(upstream_port, 0) << proxied_server.output();
  AgentProcess proxy(CMMCOMP_AGENT_PATH,
                     {"--ipp-proxy",
                      "127.0.0.1:0",
                      "--ipp-upstream",
                      "127.0.0.1:" + std::to_string(upstream_port)});
  const int proxy_port = proxy.port_after("I++ proxy listening on 127.0.0.1:");
  ASSERT_GT(proxy_port, 0) << proxy.output();

  const std::string agent = "tcp:127.0.0.1:" + std::to_string(modbus.port);
  const nlohmann::json over_modbus = run_vc({"--modbus", agent});
  const nlohmann::json over_ipp =
      run_vc({"--ipp", "127.0.0.1:" + std::to_string(direct_port), "--modbus", agent});
  const nlohmann::json through_proxy =
      run_vc({"--ipp", "127.0.0.1:" + std::to_string(proxy_port), "--ipp-proxied"});
  ASSERT_EQ(over_modbus["per_y"].size(), 3u) << over_modbus.dump();
  ASSERT_EQ(over_ipp["per_y"].size(), 3u) << over_ipp.dump();
  ASSERT_EQ(through_proxy["per_y"].size(), 3u) << through_proxy.dump();
  int compensated_passes = 0;
  for (std::size_t i = 0; i < 3; ++i) {
    const nlohmann::json& m = over_modbus["per_y"][i];
    for (const nlohmann::json* other : {&over_ipp["per_y"][i], &through_proxy["per_y"][i]}) {
      const nlohmann::json& o = *other;
      EXPECT_EQ(o["y_mm"], m["y_mm"]);
      EXPECT_EQ(o["slow"]["pass"], m["slow"]["pass"]) << o.dump() << "\n" << m.dump();
      EXPECT_EQ(o["fast_uncompensated"]["pass"], m["fast_uncompensated"]["pass"]) << o.dump();
      // The touches travel at 1e-6 mm over I++.
      EXPECT_NEAR(o["fast_uncompensated"]["max_abs_um"].get<double>(),
                  m["fast_uncompensated"]["max_abs_um"].get<double>(),
                  0.01);
    }
    const nlohmann::json& by_modbus = m["fast_compensated"]["agent"];
    const nlohmann::json& by_proxy = through_proxy["per_y"][i]["fast_compensated"]["ipp-proxy"];
    EXPECT_EQ(over_ipp["per_y"][i]["fast_compensated"]["agent"]["pass"], by_modbus["pass"]);
    EXPECT_EQ(by_proxy["pass"], by_modbus["pass"]) << by_proxy.dump() << "\n" << by_modbus.dump();
    // Modbus carries the correction as float32, the proxy at 1e-6 mm: the same to 0.01 µm.
    EXPECT_NEAR(by_proxy["max_abs_um"].get<double>(), by_modbus["max_abs_um"].get<double>(), 0.01);
    EXPECT_LT(by_proxy["max_abs_um"].get<double>(),
              m["fast_uncompensated"]["max_abs_um"].get<double>());
    compensated_passes += by_proxy["pass"].get<bool>() ? 1 : 0;
  }
  EXPECT_GT(compensated_passes, 0);
  // The proxy names the model that corrected the points (CmmcompModel), as the agent does.
  ASSERT_FALSE(through_proxy["agents"].empty()) << through_proxy.dump();
  ASSERT_FALSE(over_modbus["agents"].empty()) << over_modbus.dump();
  EXPECT_EQ(through_proxy["agents"][0]["model_id"], over_modbus["agents"][0]["model_id"]);
  EXPECT_NE(through_proxy["agents"][0]["model_id"], "0000000000000000");
}

}  // namespace
}  // namespace cmmcomp
