// SPDX-License-Identifier: MIT
/// @file cmmcomp-agent's settings and its config file (`--config /etc/cmmcomp/agent.toml`,
/// docs/agent.md): models per axis, the CAN and Modbus interfaces, the outside-domain policy and
/// the log level, validated with file:line errors as the machine file is.
#pragma once

#include <cmmcomp/fuzzy/tsk_evaluator.hpp>
#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstdint>
#include <string>
#include <vector>

#include "model_slots.hpp"

namespace cmmcomp::serving {

/// `format_version` of the agent config this library reads.
inline constexpr int kAgentConfigVersion = 1;

/// The agent's CAN interface (`[can]`). Empty `interface`: no CAN.
struct CanSettings {
  std::string interface;                                 ///< e.g. "can0", "vcan0"
  std::uint32_t base_id = plugins::can::kDefaultBaseId;  ///< 11-bit base identifier
  int heartbeat_ms = 1000;   ///< heartbeat period, 0 = off; 0 .. 3 600 000
  int part_timeout_ms = 50;  ///< longest gap between a request's frames; 1 .. 60 000
};

/// The agent's Modbus endpoint (`[modbus]`). Empty `endpoint`: no Modbus.
struct ModbusSettings {
  std::string endpoint;  ///< tcp:HOST:PORT or rtu:DEVICE:BAUD[,8N1] (plugins::ModbusEndpoint)
  int unit = 1;          ///< unit id, 1 .. 247
};

/// Everything cmmcomp-agent serves with; the command-line options fill the same struct.
struct AgentSettings {
  std::vector<ModelSlot> models;  ///< empty: the shipped default model on axis 0
  CanSettings can;
  ModbusSettings modbus;
  fuzzy::DomainPolicy outside_domain = fuzzy::DomainPolicy::kClamp;
  std::string log_level = "info";  ///< trace, debug, info, warn, error, critical, off

  /// True when the settings serve on at least one bus.
  bool serves_something() const { return !can.interface.empty() || !modbus.endpoint.empty(); }
};

/// The log levels `log_level` accepts, in increasing severity.
inline constexpr const char* kLogLevels[] = {
    "trace", "debug", "info", "warn", "error", "critical", "off"};

/// Parses an agent config (`source` names it in messages). Setup only. Throws ConfigError
/// "source:line: what is wrong" for text outside the TOML subset (io/toml_subset.hpp), a missing
/// or unsupported format_version, an unknown section or key, a value of the wrong type or out of
/// range, a model path that is empty, an endpoint or base id that does not parse, or a config that
/// serves on no bus. Relative model paths are resolved against the config file's directory.
AgentSettings parse_agent_config(const std::string& text, const std::string& source);

/// Reads and parses an agent config file (bounded read, io::read_file_bounded).
AgentSettings load_agent_config(const std::string& path);

/// What a reload of the config would change that needs a restart (the buses, the policy): one
/// line per setting, empty when nothing does. The models and the log level change in place.
std::vector<std::string> restart_needed(const AgentSettings& running, const AgentSettings& next);

}  // namespace cmmcomp::serving
