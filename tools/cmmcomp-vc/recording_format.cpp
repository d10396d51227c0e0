// SPDX-License-Identifier: MIT
/// @file Session recording formats.
#include "recording_format.hpp"

#include <chrono>
#include <cstdio>

namespace cmmcomp::vc {

std::int64_t now_us() noexcept {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

std::string format_timestamp(std::int64_t us) {
  char buf[32];
  std::snprintf(buf,
                sizeof buf,
                "%lld.%06lld",
                static_cast<long long>(us / 1000000),
                static_cast<long long>(us % 1000000));
  return buf;
}

std::string modbus_transcript_header(const std::string& label, int unit_id) {
  return "# cmmcomp modbus transcript 1\n# agent " + label + "\n# transport tcp\n# unit " +
         std::to_string(unit_id) + "\n# columns: seconds.micros tx|rx adu-hex\n";
}

std::string modbus_transcript_line(std::int64_t us,
                                   WireDirection direction,
                                   const std::uint8_t* adu,
                                   std::size_t size) {
  std::string line = format_timestamp(us);
  line += direction == WireDirection::kTx ? " tx" : " rx";
  static constexpr char kHex[] = "0123456789abcdef";
  for (std::size_t i = 0; i < size; ++i) {
    line += ' ';
    line += kHex[adu[i] >> 4];
    line += kHex[adu[i] & 0xF];
  }
  line += '\n';
  return line;
}

std::string candump_line(std::int64_t us,
                         const std::string& interface,
                         const plugins::can::Frame& f) {
  char id[8];
  std::snprintf(id, sizeof id, "%03X", static_cast<unsigned>(f.id & 0x7FFu));
  std::string line = "(" + format_timestamp(us) + ") " + interface + " " + id + "#";
  static constexpr char kHex[] = "0123456789ABCDEF";
  for (std::size_t i = 0; i < f.dlc && i < f.data.size(); ++i) {
    line += kHex[f.data[i] >> 4];
    line += kHex[f.data[i] & 0xF];
  }
  line += '\n';
  return line;
}

}  // namespace cmmcomp::vc
