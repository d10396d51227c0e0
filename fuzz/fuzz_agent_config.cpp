// SPDX-License-Identifier: MIT
/// @file libFuzzer target: cmmcomp-agent's config file (serving::parse_agent_config): the TOML
/// subset check, then toml++, then the key, type and range checks (docs/agent.md). Any
/// ConfigError is a correct answer. An accepted config must be one the agent can serve: a bus,
/// a known log level, models on distinct axes in range, ids and ranges as documented.
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <set>
#include <string>

#include "agent_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cmmcomp::serving;
  const std::string text(reinterpret_cast<const char*>(data), size);
  AgentSettings s;
  try {
    s = parse_agent_config(text, "/etc/cmmcomp/agent.toml");
  } catch (const cmmcomp::ConfigError&) {
    return 0;
  }
  if (!s.serves_something()) std::abort();
  bool level = false;
  for (const char* l : kLogLevels) level = level || s.log_level == l;
  if (!level) std::abort();
  std::set<int> axes;
  for (const ModelSlot& m : s.models) {
    if (m.axis < 0 || m.axis >= cmmcomp::compensation::kMaxAxes) std::abort();
    if (!axes.insert(m.axis).second) std::abort();
    if (!m.path.empty() && m.path[0] != '/') std::abort();  // resolved against /etc/cmmcomp
  }
  if (!s.can.interface.empty()) {
    if (s.can.base_id > 0x7FF || s.can.heartbeat_ms < 0 || s.can.heartbeat_ms > 3'600'000 ||
        s.can.part_timeout_ms < 1 || s.can.part_timeout_ms > 60'000) {
      std::abort();
    }
  }
  if (!s.modbus.endpoint.empty()) {
    if (s.modbus.unit < 1 || s.modbus.unit > 247) std::abort();
    (void)cmmcomp::plugins::ModbusEndpoint::parse(s.modbus.endpoint);  // must not throw
  }
  return 0;
}
