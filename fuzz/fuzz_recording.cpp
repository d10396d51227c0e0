// SPDX-License-Identifier: MIT
/// @file libFuzzer target: both recording parsers of cmmcomp-replay (docs/recordings.md), the
/// Modbus transcript and the candump log, chosen by the first line as load_recording does. A
/// RecordingError is a correct answer. Invariants (abort on violation): every message's line
/// is within the file, its time at most the documented latest, a CAN identifier 11 bits with
/// at most 8 data bytes, a Modbus message at least 8 bytes whose MBAP length matches.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <sstream>
#include <string>

#include "recording.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace cmmcomp::replay;
  const std::string text(reinterpret_cast<const char*>(data), size);
  const std::string first = text.substr(0, text.find('\n'));
  try {
    std::istringstream in(text);
    const RecordingFormat format = detect_format(first, "fuzz");
    const Recording r = format == RecordingFormat::kModbusTranscript
                            ? parse_modbus_transcript(in, "fuzz")
                            : parse_candump_log(in, "fuzz");
    for (const WireMessage& m : r.messages) {
      if (m.line < 1 || m.line > r.lines) std::abort();
      if (m.time_us < 0 || m.time_us > INT64_MAX / 1000) std::abort();
      if (format == RecordingFormat::kCandumpLog) {
        if (m.can_id > 0x7FF || m.bytes.size() > 8) std::abort();
      } else {
        if (m.bytes.size() < 8) std::abort();
        const std::size_t length = (std::size_t{m.bytes[4]} << 8) | m.bytes[5];
        if (length + 6 != m.bytes.size()) std::abort();
      }
    }
  } catch (const RecordingError&) {
  }
  return 0;
}
