// SPDX-License-Identifier: MIT
/// @file The agents a run talks to, from the command line.
#pragma once

#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstdint>
#include <string>
#include <vector>

namespace cmmcomp::vc {

/// One agent: LABEL=modbus:tcp:HOST:PORT or LABEL=can:IFACE[:BASE_ID]; LABEL@Y=… makes it the
/// agent of label LABEL for the points at carriage position Y only (a model per Y: several
/// agents share the label, one per Y).
struct AgentSpec {
  std::string label;
  bool has_y = false;  ///< LABEL@Y: answers only the points at y_mm
  double y_mm = 0.0;   ///< [mm]
  bool is_can = false;
  std::string endpoint;  ///< Modbus: "tcp:HOST:PORT"; CAN: the interface
  std::uint32_t can_base_id = plugins::can::kDefaultBaseId;
};

/// Parses one --agent value. Throws ConfigError with the expected forms.
AgentSpec parse_agent_spec(const std::string& text);

/// The recording file of agent `label` when several agents are recorded into `path`: the label
/// goes before the extension ("run.log" → "run.4in.log"); with one agent `path` itself.
std::string recording_path_for(const std::string& path, const std::string& label, bool several);

/// "20,50,100" → {20, 50, 100}. Throws ConfigError naming `what`.
std::vector<double> parse_number_list(const std::string& text, const std::string& what);

}  // namespace cmmcomp::vc
