// SPDX-License-Identifier: MIT
/// @file Reads the two session recording formats of docs/recordings.md — the Modbus transcript
/// and the candump -l log — into one list of wire messages. Pure parsing (no sockets), so the
/// parsers are unit-tested line by line.
#pragma once

#include <cmmcomp/exceptions.hpp>
#include <cstddef>
#include <cstdint>
#include <istream>
#include <stdexcept>
#include <string>
#include <vector>

namespace cmmcomp::replay {

/// An unreadable recording: what() is "FILE:LINE: what is wrong".
class RecordingError : public ConfigError {
 public:
  using ConfigError::ConfigError;
};

enum class RecordingFormat : std::uint8_t {
  kModbusTranscript,  ///< "# cmmcomp modbus transcript 1"
  kCandumpLog,        ///< "(SECONDS.MICROS) IFACE ID#DATA"
};

const char* to_string(RecordingFormat f) noexcept;

/// One message as it crossed the wire.
struct WireMessage {
  int line = 0;                     ///< 1-based line in the file
  std::int64_t time_us = 0;         ///< recorded wall-clock time, µs since the epoch
  bool from_controller = false;     ///< Modbus: "tx"; CAN: decided later from the identifier
  std::uint32_t can_id = 0;         ///< CAN: the 11-bit identifier (Modbus: 0)
  std::string interface;            ///< CAN: the interface column (Modbus: empty)
  std::vector<std::uint8_t> bytes;  ///< Modbus: the whole ADU; CAN: the data bytes
};

/// A parsed recording, messages in file order.
struct Recording {
  std::string source;  ///< file name used in messages
  RecordingFormat format = RecordingFormat::kModbusTranscript;
  std::vector<WireMessage> messages;
  int lines = 0;     ///< lines read
  int comments = 0;  ///< comment and blank lines skipped
};

/// The format of a recording from its first non-empty line (a transcript starts with its
/// header line; a candump log with '('). Throws RecordingError ("SOURCE:1: …") for neither.
RecordingFormat detect_format(const std::string& first_line, const std::string& source);

/// Parses a Modbus transcript (format 1). Comment lines ('#') anywhere are skipped; the first
/// line must be the header. Throws RecordingError naming the line and what is wrong: a wrong
/// header or version, a bad timestamp, a direction other than tx/rx, a byte that is not two
/// lower-case hex digits, fewer than 8 bytes, or an MBAP length that disagrees with the bytes.
Recording parse_modbus_transcript(std::istream& in, const std::string& source);

/// Parses a candump -l log: "(SECONDS.MICROS) IFACE ID#DATA" per line (classic CAN, 3-digit
/// 11-bit identifiers, 0..8 data bytes; an 8-digit extended identifier or a remote frame is an
/// error, as the protocol has none). Blank lines and lines starting with '#' are skipped.
Recording parse_candump_log(std::istream& in, const std::string& source);

/// Opens `path`, detects its format and parses it. Throws RecordingError when the file cannot
/// be read or is not a recording.
Recording load_recording(const std::string& path);

/// "00 01 0a" (lower case, one space) — how reports print Modbus bytes.
std::string hex_bytes(const std::vector<std::uint8_t>& bytes);

}  // namespace cmmcomp::replay
