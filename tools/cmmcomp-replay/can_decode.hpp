// SPDX-License-Identifier: MIT
/// @file Names and values of the signals of a cmmcomp CAN frame (docs/protocol-can.md,
/// cmmcomp.dbc), so a replay mismatch says "RAE" and "µm" instead of "byte 1".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "field_value.hpp"

namespace cmmcomp::replay {

/// Every signal of frame `id`#`data` of the protocol at `base_id` (request, response, reject or
/// heartbeat; multiplexed signals of the frame's part or page only), each with the bytes it
/// spans. Another identifier: no fields.
std::vector<FieldValue> decode_can_frame(std::uint32_t base_id,
                                         std::uint32_t id,
                                         const std::vector<std::uint8_t>& data);

/// "301#0001CA0C20F53A03" (candump notation).
std::string format_can_frame(std::uint32_t id, const std::vector<std::uint8_t>& data);

/// One line about the answer frames to one request, e.g. "RAE -5.3 µm corr (5.3, 0, 0) µm
/// model 9149ab07 U95 RAE 0.68 µm" (U95 only with the interval part, protocol version 2) or
/// "reject: timeout between parts (seq 3, part 1)".
std::string summarize_can_answer(std::uint32_t base_id,
                                 const std::vector<std::uint32_t>& ids,
                                 const std::vector<std::vector<std::uint8_t>>& frames);

}  // namespace cmmcomp::replay
