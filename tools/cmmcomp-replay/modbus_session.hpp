// SPDX-License-Identifier: MIT
/// @file Replay of Modbus transcripts: in process through the plugin's own frame path
/// (plugins::ModbusTcpAduResponder), or against a live agent over Modbus TCP.
#pragma once

#include <cmmcomp/compensation/move_compensator.hpp>
#include <cstdint>
#include <memory>
#include <string>

#include "session.hpp"

namespace cmmcomp::replay {

/// In process: each request ADU goes through libmodbus receive, ModbusRequestHandler and
/// modbus_reply exactly as in cmmcomp-agent's Modbus server. `compensator` must outlive it.
std::unique_ptr<Session> make_modbus_session(const compensation::MoveCompensator& compensator,
                                             std::uint8_t unit_id);

/// Live: connects to a Modbus TCP agent at `endpoint` ("tcp:HOST:PORT") and sends each request
/// ADU as recorded. Throws cmmcomp::Error when it cannot connect.
std::unique_ptr<Session> make_modbus_live_session(const std::string& endpoint);

}  // namespace cmmcomp::replay
