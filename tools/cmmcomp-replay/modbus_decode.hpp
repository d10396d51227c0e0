// SPDX-License-Identifier: MIT
/// @file Names and values of the bytes of a Modbus TCP ADU with the register map of
/// docs/protocol-modbus.md, so a replay mismatch says "RAE" and "µm" instead of "byte 33".
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "field_value.hpp"

namespace cmmcomp::replay {

/// Every field of request ADU `adu`: MBAP header, function code, addresses, counts and the
/// written registers by name (axis, direction, PV, …, sequence).
std::vector<FieldValue> decode_modbus_request(const std::vector<std::uint8_t>& adu);

/// Every field of answer ADU `adu` to `request`: MBAP header, function code or exception, byte
/// count and the registers read by name (sequence, status, flags, MPE … model id, counters).
std::vector<FieldValue> decode_modbus_answer(const std::vector<std::uint8_t>& request,
                                             const std::vector<std::uint8_t>& adu);

/// One line about a request, e.g. "FC23 seq 1 axis 0 dir (-1, 0, 0) PV 100 PD 60 AV 16 AD 10
/// Y 0".
std::string summarize_modbus_request(const std::vector<std::uint8_t>& adu);

/// One line about an answer, e.g. "status 0 (ok) RAE -5.298 µm corr (5.298, -0, -0) µm model
/// c2fc35069149ab07", or "exception 03 (illegal data value)".
std::string summarize_modbus_answer(const std::vector<std::uint8_t>& request,
                                    const std::vector<std::uint8_t>& adu);

}  // namespace cmmcomp::replay
