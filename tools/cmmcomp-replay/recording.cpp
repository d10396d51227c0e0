// SPDX-License-Identifier: MIT
/// @file Parsers of the Modbus transcript and the candump log (docs/recordings.md).
#include "recording.hpp"

#include <cstdio>
#include <fstream>
#include <limits>

namespace cmmcomp::replay {

namespace {

constexpr const char* kTranscriptHeader = "# cmmcomp modbus transcript";

[[noreturn]] void fail(const std::string& source, int line, const std::string& what) {
  throw RecordingError(source + ":" + std::to_string(line) + ": " + what);
}

int hex_digit(char c, bool upper) {
  if (c >= '0' && c <= '9') return c - '0';
  if (!upper && c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (upper && c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

/// The latest time a recording may carry [µs]: replay hands times to the handlers in int64 ns,
/// which end at 9 223 372 036.854775807 s (year 2262).
constexpr std::int64_t kLatestTimeUs = std::numeric_limits<std::int64_t>::max() / 1000;

/// "SECONDS.MICROS" with exactly six digits of microseconds, in µs, at most kLatestTimeUs;
/// false if malformed or later.
bool parse_timestamp(const std::string& text, std::int64_t& us) {
  const std::size_t dot = text.find('.');
  if (dot == std::string::npos || dot == 0 || dot > 10 || text.size() != dot + 7) return false;
  std::int64_t v = 0;
  for (std::size_t i = 0; i < text.size(); ++i) {
    if (i == dot) continue;
    if (text[i] < '0' || text[i] > '9') return false;
    v = v * 10 + (text[i] - '0');
  }
  if (v > kLatestTimeUs) return false;
  us = v;
  return true;
}

std::vector<std::string> split_spaces(const std::string& line) {
  std::vector<std::string> parts;
  std::size_t begin = 0;
  while (begin <= line.size()) {
    const std::size_t end = line.find(' ', begin);
    parts.push_back(line.substr(begin, end == std::string::npos ? std::string::npos : end - begin));
    if (end == std::string::npos) break;
    begin = end + 1;
  }
  return parts;
}

void strip_cr(std::string& line) {
  if (!line.empty() && line.back() == '\r') line.pop_back();
}

}  // namespace

const char* to_string(RecordingFormat f) noexcept {
  return f == RecordingFormat::kModbusTranscript ? "Modbus transcript" : "candump log";
}

RecordingFormat detect_format(const std::string& first_line, const std::string& source) {
  if (first_line.rfind(kTranscriptHeader, 0) == 0) return RecordingFormat::kModbusTranscript;
  if (!first_line.empty() && first_line[0] == '(') return RecordingFormat::kCandumpLog;
  fail(source,
       1,
       "not a recording: expected '# cmmcomp modbus transcript 1' (Modbus) or "
       "'(SECONDS.MICROS) IFACE ID#DATA' (candump -l), got '" +
           first_line.substr(0, 60) + "'");
}

Recording parse_modbus_transcript(std::istream& in, const std::string& source) {
  Recording r;
  r.source = source;
  r.format = RecordingFormat::kModbusTranscript;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    strip_cr(line);
    if (n == 1) {
      if (line.rfind(kTranscriptHeader, 0) != 0) {
        fail(source, n, "the first line must be '# cmmcomp modbus transcript 1'");
      }
      const std::string version = line.substr(std::string(kTranscriptHeader).size());
      if (version != " 1") {
        fail(source,
             n,
             "transcript version '" + version.substr(version.empty() ? 0 : 1) +
                 "' is not supported (this reader knows version 1)");
      }
      ++r.comments;
      continue;
    }
    if (line.empty() || line[0] == '#') {
      ++r.comments;
      continue;
    }
    const std::vector<std::string> parts = split_spaces(line);
    if (parts.size() < 3) {
      fail(source, n, "expected 'SECONDS.MICROS tx|rx XX XX …', got '" + line.substr(0, 60) + "'");
    }
    WireMessage m;
    m.line = n;
    if (!parse_timestamp(parts[0], m.time_us)) {
      fail(source,
           n,
           "timestamp '" + parts[0] +
               "' is not SECONDS.MICROS (6 digits after the point, at most 9223372036.854775)");
    }
    if (parts[1] != "tx" && parts[1] != "rx") {
      fail(source, n, "direction '" + parts[1] + "' is neither tx nor rx");
    }
    m.from_controller = parts[1] == "tx";
    for (std::size_t i = 2; i < parts.size(); ++i) {
      const std::string& b = parts[i];
      const int hi = b.size() == 2 ? hex_digit(b[0], false) : -1;
      const int lo = b.size() == 2 ? hex_digit(b[1], false) : -1;
      if (hi < 0 || lo < 0) {
        fail(source,
             n,
             "byte " + std::to_string(i - 2) + " '" + b + "' is not two lower-case hex digits");
      }
      m.bytes.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
    }
    if (m.bytes.size() < 8) {
      fail(source,
           n,
           "an ADU has at least 8 bytes (MBAP header and function code), this line has " +
               std::to_string(m.bytes.size()));
    }
    const std::size_t length = static_cast<std::size_t>(m.bytes[4] << 8 | m.bytes[5]);
    if (length + 6 != m.bytes.size()) {
      fail(source,
           n,
           "MBAP length " + std::to_string(length) + " says " + std::to_string(length + 6) +
               " bytes, the line has " + std::to_string(m.bytes.size()));
    }
    r.messages.push_back(std::move(m));
  }
  if (n == 0) fail(source, 1, "empty file");
  r.lines = n;
  return r;
}

Recording parse_candump_log(std::istream& in, const std::string& source) {
  Recording r;
  r.source = source;
  r.format = RecordingFormat::kCandumpLog;
  std::string line;
  int n = 0;
  while (std::getline(in, line)) {
    ++n;
    strip_cr(line);
    if (line.empty() || line[0] == '#') {
      ++r.comments;
      continue;
    }
    const std::vector<std::string> parts = split_spaces(line);
    if (parts.size() != 3 && !(parts.size() == 4 && (parts[3] == "T" || parts[3] == "R"))) {
      fail(
          source, n, "expected '(SECONDS.MICROS) IFACE ID#DATA', got '" + line.substr(0, 60) + "'");
    }
    WireMessage m;
    m.line = n;
    const std::string& ts = parts[0];
    if (ts.size() < 3 || ts.front() != '(' || ts.back() != ')' ||
        !parse_timestamp(ts.substr(1, ts.size() - 2), m.time_us)) {
      fail(
          source,
          n,
          "timestamp '" + ts +
              "' is not (SECONDS.MICROS) with 6 digits after the point, at most 9223372036.854775");
    }
    if (parts[1].empty()) fail(source, n, "the interface is empty");
    m.interface = parts[1];
    const std::string& frame = parts[2];
    const std::size_t hash = frame.find('#');
    if (hash == std::string::npos) fail(source, n, "frame '" + frame + "' has no '#' (ID#DATA)");
    const std::string id = frame.substr(0, hash);
    const std::string data = frame.substr(hash + 1);
    if (id.size() == 8)
      fail(source, n, "extended identifier '" + id + "': the protocol uses 11-bit ids");
    if (id.size() != 3) fail(source, n, "identifier '" + id + "' is not 3 hex digits");
    std::uint32_t v = 0;
    for (char c : id) {
      int d = hex_digit(c, true);
      if (d < 0) d = hex_digit(c, false);
      if (d < 0) fail(source, n, "identifier '" + id + "' is not hexadecimal");
      v = v * 16 + static_cast<std::uint32_t>(d);
    }
    if (v > 0x7FF) fail(source, n, "identifier '" + id + "' is above 0x7FF");
    m.can_id = v;
    if (!data.empty() && (data[0] == 'R' || data[0] == '#')) {
      fail(source,
           n,
           "remote or CAN FD frame '" + frame + "': the protocol uses classic data frames");
    }
    if (data.size() % 2 != 0 || data.size() > 16) {
      fail(source, n, "data '" + data + "' is not 0 to 8 bytes of two hex digits each");
    }
    for (std::size_t i = 0; i < data.size(); i += 2) {
      int hi = hex_digit(data[i], true), lo = hex_digit(data[i + 1], true);
      if (hi < 0) hi = hex_digit(data[i], false);
      if (lo < 0) lo = hex_digit(data[i + 1], false);
      if (hi < 0 || lo < 0) fail(source, n, "data '" + data + "' is not hexadecimal");
      m.bytes.push_back(static_cast<std::uint8_t>(hi * 16 + lo));
    }
    r.messages.push_back(std::move(m));
  }
  if (n == 0) fail(source, 1, "empty file");
  r.lines = n;
  return r;
}

Recording load_recording(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw RecordingError(path + ": cannot open the file");
  std::string first;
  while (std::getline(in, first)) {
    strip_cr(first);
    if (!first.empty()) break;
  }
  if (first.empty()) fail(path, 1, "empty file");
  const RecordingFormat format = detect_format(first, path);
  in.clear();
  in.seekg(0);
  return format == RecordingFormat::kModbusTranscript ? parse_modbus_transcript(in, path)
                                                      : parse_candump_log(in, path);
}

std::string hex_bytes(const std::vector<std::uint8_t>& bytes) {
  std::string s;
  char buf[4];
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%02x", bytes[i]);
    if (i > 0) s += ' ';
    s += buf;
  }
  return s;
}

}  // namespace cmmcomp::replay
