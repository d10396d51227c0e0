// SPDX-License-Identifier: MIT
/// @file The two session recording formats (docs/recordings.md): the Modbus transcript and the
/// candump log. Pure formatting, so the formats are tested exactly.
#pragma once

#include <cmmcomp/plugins/can_protocol.hpp>
#include <cstddef>
#include <cstdint>
#include <string>

namespace cmmcomp::vc {

/// Wall-clock time of a recorded line, microseconds since the Unix epoch.
std::int64_t now_us() noexcept;

/// "SECONDS.MICROS" with six digits after the point, e.g. "1763860000.000100".
std::string format_timestamp(std::int64_t us);

/// Who sent an ADU: the controller (the virtual controller, "tx") or the agent ("rx").
enum class WireDirection { kTx, kRx };

/// The first lines of a Modbus transcript, each starting with "# " and ending with '\n'.
/// Deterministic: no time, no port.
std::string modbus_transcript_header(const std::string& label, int unit_id);

/// One transcript line: "SECONDS.MICROS tx|rx HH HH …\n" (lower-case hex, one space between
/// bytes, the whole ADU: MBAP header and PDU).
std::string modbus_transcript_line(std::int64_t us,
                                   WireDirection direction,
                                   const std::uint8_t* adu,
                                   std::size_t size);

/// One candump -l line: "(SECONDS.MICROS) IFACE III#DDDDDDDDDDDDDDDD\n" (identifier as 3
/// upper-case hex digits, data upper-case hex, two digits per byte, no separator).
std::string candump_line(std::int64_t us,
                         const std::string& interface,
                         const plugins::can::Frame& f);

}  // namespace cmmcomp::vc
