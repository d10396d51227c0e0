// SPDX-License-Identifier: MIT
/// @file The agent config file (tools/serving/agent_config.hpp, docs/agent.md): what it sets,
/// and a clear file:line error for each kind of mistake.
#include <gtest/gtest.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/io/file_io.hpp>
#include <string>

#include "agent_config.hpp"

namespace cmmcomp::serving {
namespace {

std::string error_of(const std::string& text) {
  try {
    parse_agent_config(text, "/etc/cmmcomp/agent.toml");
  } catch (const ConfigError& e) {
    return e.what();
  }
  return "";
}

constexpr const char* kFull = R"(format_version = 1
log_level = "debug"
outside_domain = "reject"
[models]
0 = "models/x.json"
2 = "/var/lib/cmmcomp/z.json"
3 = "default"
[can]
interface = "vcan0"
base_id = "0x310"
heartbeat_ms = 0
part_timeout_ms = 20
[modbus]
endpoint = "tcp:[::1]:1502"
unit = 7
)";

TEST(AgentConfig, ReadsEverySetting) {
  const AgentSettings s = parse_agent_config(kFull, "/etc/cmmcomp/agent.toml");
  EXPECT_EQ(s.log_level, "debug");
  EXPECT_EQ(s.outside_domain, fuzzy::DomainPolicy::kReject);
  ASSERT_EQ(s.models.size(), 3u);
  EXPECT_EQ(s.models[0].axis, 0);
  EXPECT_EQ(s.models[0].path, "/etc/cmmcomp/models/x.json");  // relative to the config's folder
  EXPECT_EQ(s.models[1].path, "/var/lib/cmmcomp/z.json");
  EXPECT_EQ(s.models[2].axis, 3);
  EXPECT_EQ(s.models[2].path, "");  // the shipped model
  EXPECT_EQ(s.can.interface, "vcan0");
  EXPECT_EQ(s.can.base_id, 0x310u);
  EXPECT_EQ(s.can.heartbeat_ms, 0);
  EXPECT_EQ(s.can.part_timeout_ms, 20);
  EXPECT_EQ(s.modbus.endpoint, "tcp:[::1]:1502");
  EXPECT_EQ(s.modbus.unit, 7);
}

TEST(AgentConfig, DefaultsAreTheCommandLineDefaults) {
  const AgentSettings s = parse_agent_config(
      "format_version = 1\n[modbus]\nendpoint = \"tcp:127.0.0.1:1502\"\n", "a.toml");
  const AgentSettings d;
  EXPECT_TRUE(s.models.empty());
  EXPECT_EQ(s.log_level, d.log_level);
  EXPECT_EQ(s.outside_domain, d.outside_domain);
  EXPECT_EQ(s.modbus.unit, 1);
  EXPECT_TRUE(s.can.interface.empty());
}

TEST(AgentConfig, EachMistakeNamesTheFileAndLine) {
  const std::string head = "format_version = 1\n[modbus]\nendpoint = \"tcp:127.0.0.1:1502\"\n";
  const struct {
    std::string text;
    std::string expected;
  } cases[] = {
      {"[modbus]\nendpoint = \"tcp:1.2.3.4:5\"\n", "agent.toml: missing 'format_version'"},
      {"format_version = 2\n" + head.substr(19), "agent.toml:1: format_version must be 1"},
      {head + "speed = 3\n", "agent.toml:4: unknown key 'modbus.speed'"},
      {head + "[modbuss]\nunit = 2\n", "agent.toml:4: unknown section '[modbuss]'"},
      {"format_version = 1\nlog_level = \"loud\"\n[modbus]\nendpoint = \"tcp:1.2.3.4:5\"\n",
       "agent.toml:2: log_level 'loud' is not one of"},
      {"format_version = 1\noutside_domain = \"wrap\"\n[modbus]\nendpoint = \"tcp:1.2.3.4:5\"\n",
       "agent.toml:2: outside_domain 'wrap' is not clamp, extrapolate or reject"},
      {head + "unit = 300\n", "agent.toml:4: 'modbus.unit' = 300 is outside 1 .. 247"},
      {head + "unit = \"1\"\n", "agent.toml:4: 'modbus.unit' must be an integer"},
      {"format_version = 1\n[modbus]\nendpoint = \"tcp:localhost:99999\"\n",
       "agent.toml:3: Modbus endpoint 'tcp:localhost:99999'"},
      {head + "[models]\n4 = \"m.json\"\n",
       "agent.toml:5: 'models.4': the key is the axis, 0 .. 3"},
      {head + "[models]\nx = \"m.json\"\n", "agent.toml:5: 'models.x': the key is the axis"},
      {head + "[models]\n0 = \"\"\n", "agent.toml:5: 'models.0' names no file"},
      {head + "[models]\n0 = \"a.json\"\n00 = \"b.json\"\n",
       "agent.toml:6: 'models.00': the key is the axis"},
      {head + "[models]\n-0 = \"a.json\"\n", "agent.toml:5: 'models.-0': the key is the axis"},
      {head + "[can]\ninterface = \"can0123456789abcd\"\n", "agent.toml:5: CAN interface name"},
      {head + "[can]\ninterface = \"can/0\"\n",
       "agent.toml:5: CAN interface name 'can/0' has a '/'"},
      {head + "[can]\ninterface = \"can 0\"\n", "has a '/', a blank"},
      {head + "[can]\ninterface = \"can0\"\nbase_id = \" 0x300\"\n", "agent.toml:6: --can-base-id"},
      {head + "[can]\ninterface = \"can0\"\nbase_id = \"-0\"\n", "agent.toml:6: --can-base-id"},
      {head + "[can]\ninterface = \"can0\"\nbase_id = \"0x800\"\n", "agent.toml:6: "},
      {head + "[can]\nbase_id = \"0x300\"\n", "[can] needs 'interface'"},
      {"format_version = 1\nlog_level = \"info\"\n", "agent.toml: serves on no bus"},
      {head + "unit = [1, 2]\n", "agent.toml:4:8: syntax error"},
      {"format_version = 1\nlog_level = \"a\\u0007b\"\n", "control character 0x07"},
  };
  for (const auto& c : cases) {
    const std::string e = error_of(c.text);
    EXPECT_NE(e.find(c.expected), std::string::npos) << "got: " << e << "\nfor:\n" << c.text;
  }
}

TEST(AgentConfig, RestartNeededNamesWhatCannotChangeInPlace) {
  const AgentSettings a = parse_agent_config(kFull, "/etc/cmmcomp/agent.toml");
  AgentSettings b = a;
  EXPECT_TRUE(restart_needed(a, b).empty());
  b.models.clear();
  b.log_level = "info";
  EXPECT_TRUE(restart_needed(a, b).empty());  // models and log level change in place
  b.modbus.unit = 2;
  b.outside_domain = fuzzy::DomainPolicy::kClamp;
  EXPECT_EQ(restart_needed(a, b), (std::vector<std::string>{"[modbus]", "outside_domain"}));
}

// The shipped example (packaging/agent.toml, installed as /etc/cmmcomp/agent.toml) and the one in
// docs/agent.md are valid configs.
TEST(AgentConfig, TheShippedExampleAndTheDocumentedOneParse) {
  const AgentSettings shipped = load_agent_config(CMMCOMP_SHIPPED_AGENT_CONFIG);
  EXPECT_EQ(shipped.modbus.endpoint, "tcp:0.0.0.0:502");
  ASSERT_EQ(shipped.models.size(), 1u);
  EXPECT_EQ(shipped.models[0].path, "");
  const std::string doc =
      io::read_file_bounded(CMMCOMP_AGENT_DOC, "document", io::kMaxTextFileBytes);
  const std::size_t begin = doc.find("```toml\n");
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = doc.find("```", begin + 8);
  const AgentSettings documented =
      parse_agent_config(doc.substr(begin + 8, end - begin - 8), "docs/agent.md");
  EXPECT_FALSE(documented.can.interface.empty());
  EXPECT_FALSE(documented.modbus.endpoint.empty());
}

}  // namespace
}  // namespace cmmcomp::serving
