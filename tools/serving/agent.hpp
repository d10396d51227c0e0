// SPDX-License-Identifier: MIT
/// @file cmmcomp-agent's runtime: serves the per-move compensator over SocketCAN
/// (docs/protocol-can.md) and/or Modbus TCP/RTU (docs/protocol-modbus.md) until a signal stops it.
///
/// Threads: one per bus, each running its server's loop; the main thread only waits for
/// signals (blocked everywhere, taken with sigtimedwait, so no handler runs in a server
/// thread). SIGHUP reloads every model file: a file that fails keeps the old model serving
/// (the compensator's publish is a wait-free hot swap for the serving threads). SIGTERM and
/// SIGINT stop the servers and exit 0 after logging their counters.
#pragma once

#include <string>

#include "agent_config.hpp"
#include "ipp_proxy.hpp"

namespace cmmcomp::serving {

/// Loads the models of `settings` (the shipped default model on axis 0, with a warning, when it
/// names none) and serves them on the buses it names until SIGTERM or SIGINT; `config_path`
/// (empty: none) is re-read on SIGHUP. With `check`, returns after loading the models. Exit
/// status: 0; 1 when a server failed; 2 when a model could not be loaded at start.
int run_agent(AgentSettings settings, const std::string& config_path, bool check);

/// Loads the models of `settings` as run_agent does and runs the compensating I++ DME proxy
/// (ipp_proxy.hpp) until SIGTERM or SIGINT; SIGHUP reloads the model files (a file that fails
/// keeps the old model serving). Same exit status as run_agent.
int run_ipp_proxy(const AgentSettings& settings, const IppProxyOptions& proxy, bool check);

}  // namespace cmmcomp::serving
