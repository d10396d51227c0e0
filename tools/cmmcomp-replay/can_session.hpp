// SPDX-License-Identifier: MIT
/// @file Replay of candump logs: in process through the plugin's state machine
/// (CanRequestHandler, the recorded timestamps driving its part timeout), or against
/// a live agent on a CAN interface.
#pragma once

#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cstdint>
#include <memory>
#include <string>

#include "session.hpp"

namespace cmmcomp::replay {

/// In process. `base_id` and `part_timeout` as cmmcomp-agent's --can-base-id and
/// --can-part-timeout-ms. `compensator` must outlive the session.
std::unique_ptr<Session> make_can_session(const compensation::MoveCompensator& compensator,
                                          std::uint32_t base_id,
                                          std::chrono::nanoseconds part_timeout);

/// Live: sends each request frame on `interface` (raw CAN socket; paced like the recording,
/// as canplayer does) and collects the agent's answer frames (base + 1, base + 2). Throws
/// cmmcomp::Error when the interface cannot be opened (no AF_CAN: run it in the UML guest).
std::unique_ptr<Session> make_can_live_session(const std::string& interface, std::uint32_t base_id);

}  // namespace cmmcomp::replay
