// SPDX-License-Identifier: MIT
/// @file cmmcomp-vc against live cmmcomp-agent processes over Modbus TCP on loopback: the fast
/// setting's compensated length errors are smaller than the uncompensated ones, the recording is
/// a well-formed transcript, two runs with the same seed record the same bytes, two agents can
/// be compared in one run, and an unreachable agent is exit status 2.
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "line_forms.hpp"
#include "tools/agent/agent_process.hpp"

#ifndef CMMCOMP_AGENT_PATH
#error "CMMCOMP_AGENT_PATH must name the cmmcomp-agent executable"
#endif
#ifndef CMMCOMP_VC_PATH
#error "CMMCOMP_VC_PATH must name the cmmcomp-vc executable"
#endif

namespace cmmcomp {
namespace {

using namespace std::chrono_literals;
using test::AgentProcess;

using test::RunningAgent;

/// Starts an agent with the shipped model on a free loopback port.
RunningAgent start_agent(int salt) {
  std::string why;
  RunningAgent a = test::start_modbus_agent(CMMCOMP_AGENT_PATH, {}, salt, &why);
  if (!a.process) ADD_FAILURE() << why;
  return a;
}

struct VcRun {
  int status = -1;
  std::string output;
};

VcRun run_vc(const std::vector<std::string>& args) {
  AgentProcess vc(CMMCOMP_VC_PATH, args);
  VcRun r;
  r.status = vc.wait_exit(50s);
  r.output = vc.output();
  return r;
}

nlohmann::json json_of(const std::string& output) {
  const auto first = output.find('{');
  const auto last = output.rfind('}');
  if (first == std::string::npos || last == std::string::npos) return {};
  return nlohmann::json::parse(output.substr(first, last - first + 1));
}

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line)) out.push_back(line);
  return out;
}

/// The transcript without its timestamps (what must be identical between runs).
std::string without_timestamps(const std::vector<std::string>& lines) {
  std::string out;
  for (const auto& l : lines) out += (l.empty() || l[0] == '#' ? l : l.substr(l.find(' '))) + "\n";
  return out;
}

const std::vector<std::string> kReduced = {
    "--lengths", "20,100,400", "--y", "0,250", "--repeats", "1", "--seed", "7", "--json"};

TEST(VcModbusE2e, CompensationShrinksFastLengthErrorsAndRecordsTheSession) {
  RunningAgent agent = start_agent(1);
  ASSERT_TRUE(agent.process);
  const std::string rec = ::testing::TempDir() + "vc_e2e_" + std::to_string(getpid()) + ".mbtx";
  std::vector<std::string> args = kReduced;
  args.insert(args.end(),
              {"--modbus", "tcp:127.0.0.1:" + std::to_string(agent.port), "--record", rec});
  const VcRun first = run_vc(args);
  ASSERT_EQ(first.status, 0) << first.output;
  const nlohmann::json j = json_of(first.output);
  ASSERT_EQ(j["cases"].size(), 6u) << first.output;
  for (const auto& c : j["cases"]) {
    const double unc = c["fast_uncompensated_um"].get<double>();
    const double comp = c["fast_compensated_um"]["agent"].get<double>();
    EXPECT_LT(std::fabs(comp), std::fabs(unc)) << c.dump();
    EXPECT_GT(std::fabs(unc), c["mpe_e_um"].get<double>()) << "fast uncompensated should fail";
  }
  EXPECT_GT(j["speedup"].get<double>(), 2.0);
  EXPECT_EQ(j["agents"][0]["model_id"].get<std::string>().size(), 16u);

  // The transcript: header comments, then strictly alternating tx/rx ADUs (FC23 and its
  // answer), one pair per fast point: 3 lengths × 2 Y × 2 faces.
  const std::vector<std::string> lines = lines_of(rec);
  ASSERT_GT(lines.size(), 5u);
  EXPECT_EQ(lines[0], "# cmmcomp modbus transcript 1");
  std::size_t adus = 0;
  std::vector<std::uint8_t> request;
  for (const auto& l : lines) {
    if (l[0] == '#') continue;
    vc::test::TranscriptLine t;
    ASSERT_TRUE(vc::test::parse_transcript_line(l, t)) << l;
    ASSERT_GE(t.bytes.size(), 9u) << l;
    EXPECT_EQ(t.bytes.size(), 6u + ((std::size_t{t.bytes[4]} << 8) | t.bytes[5])) << l;
    EXPECT_EQ(t.bytes[6], 1u) << "unit id";
    EXPECT_EQ(t.bytes[7], 0x17u) << "FC23";
    if (adus % 2 == 0) {
      EXPECT_EQ(t.direction, "tx") << l;
      EXPECT_EQ(t.bytes.size(), 67u) << l;  // MBAP 7 + FC23 with 25 registers written
      request = t.bytes;
    } else {
      EXPECT_EQ(t.direction, "rx") << l;
      // MBAP 7 + FC 1 + count 1 + 33 registers: the result and its interval (protocol 2).
      EXPECT_EQ(t.bytes.size(), 9u + 2u * (23u + 10u)) << l;
      EXPECT_TRUE(t.bytes[0] == request[0] && t.bytes[1] == request[1]) << "transaction id";
    }
    ++adus;
  }
  EXPECT_EQ(adus, 2u * 12u);

  // Same seed, same model: the same bytes on the wire and the same report.
  const VcRun second = run_vc(args);
  ASSERT_EQ(second.status, 0) << second.output;
  EXPECT_EQ(without_timestamps(lines_of(rec)), without_timestamps(lines));
  EXPECT_EQ(json_of(second.output), j);
  std::remove(rec.c_str());
}

TEST(VcModbusE2e, ComparesTwoAgentsAndRecordsEach) {
  RunningAgent a = start_agent(2);
  RunningAgent b = start_agent(3);
  ASSERT_TRUE(a.process && b.process);
  const std::string rec = ::testing::TempDir() + "vc_two_" + std::to_string(getpid()) + ".mbtx";
  std::vector<std::string> args = kReduced;
  args.insert(args.end(),
              {"--agent",
               "4in=modbus:tcp:127.0.0.1:" + std::to_string(a.port),
               "--agent",
               "other=modbus:tcp:127.0.0.1:" + std::to_string(b.port),
               "--record",
               rec});
  const VcRun r = run_vc(args);
  ASSERT_EQ(r.status, 0) << r.output;
  const nlohmann::json j = json_of(r.output);
  ASSERT_EQ(j["agents"].size(), 2u);
  for (const auto& c : j["cases"]) {
    // The same model behind both: the same corrections.
    EXPECT_DOUBLE_EQ(c["fast_compensated_um"]["4in"].get<double>(),
                     c["fast_compensated_um"]["other"].get<double>());
  }
  const std::string ra = ::testing::TempDir() + "vc_two_" + std::to_string(getpid()) + ".4in.mbtx";
  const std::string rb =
      ::testing::TempDir() + "vc_two_" + std::to_string(getpid()) + ".other.mbtx";
  EXPECT_EQ(lines_of(ra).size(), 5u + 24u);
  EXPECT_EQ(lines_of(rb).size(), 5u + 24u);
  std::remove(ra.c_str());
  std::remove(rb.c_str());
}

TEST(VcModbusE2e, UnreachableAgentIsExitStatusTwo) {
  const VcRun r = run_vc({"--modbus", "tcp:127.0.0.1:1", "--lengths", "20"});
  EXPECT_EQ(r.status, 2) << r.output;
  EXPECT_NE(r.output.find("unreachable"), std::string::npos) << r.output;
}

TEST(VcModbusE2e, BadOptionsAreExitStatusTwo) {
  EXPECT_EQ(run_vc({"--modbus", "udp:1.2.3.4:5"}).status, 2);
  EXPECT_EQ(run_vc({"--lengths", "20"}).status, 2);  // no agent
  EXPECT_EQ(run_vc({"--nonsense"}).status, 2);
  EXPECT_EQ(run_vc({"--modbus", "tcp:127.0.0.1:1", "--timeout-ms", "0"}).status, 2);
  EXPECT_EQ(run_vc({"--help"}).status, 0);
  EXPECT_EQ(run_vc({"--modbus", "tcp:127.0.0.1:1", "--fast", "pv=-3"}).status, 2);
}

}  // namespace
}  // namespace cmmcomp
