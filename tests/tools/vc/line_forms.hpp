// SPDX-License-Identifier: MIT
/// @file Strict parsers of the two recording line forms (docs/recordings.md), for the tests. By
/// hand: std::regex trips GCC 12's -Wmaybe-uninitialized under the sanitizers.
#pragma once

#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

namespace cmmcomp::vc::test {

inline bool all_of(const std::string& s, const char* allowed) {
  return !s.empty() && s.find_first_not_of(allowed) == std::string::npos;
}

/// "SECONDS.MICROS": digits, a point, exactly six digits.
inline bool is_timestamp(const std::string& s) {
  const auto dot = s.find('.');
  return dot != std::string::npos && dot > 0 && s.size() - dot - 1 == 6 &&
         all_of(s.substr(0, dot), "0123456789") && all_of(s.substr(dot + 1), "0123456789");
}

struct TranscriptLine {
  std::string timestamp;
  std::string direction;  ///< "tx" or "rx"
  std::vector<std::uint8_t> bytes;
};

/// "SECONDS.MICROS tx|rx hh hh …" with single spaces and lower-case hex, nothing else.
inline bool parse_transcript_line(const std::string& line, TranscriptLine& out) {
  std::istringstream in(line);
  TranscriptLine t;
  if (!(in >> t.timestamp >> t.direction) || !is_timestamp(t.timestamp) ||
      (t.direction != "tx" && t.direction != "rx")) {
    return false;
  }
  std::string canonical = t.timestamp + " " + t.direction;
  std::string b;
  while (in >> b) {
    if (b.size() != 2 || !all_of(b, "0123456789abcdef")) return false;
    t.bytes.push_back(static_cast<std::uint8_t>(std::stoul(b, nullptr, 16)));
    canonical += " " + b;
  }
  if (canonical != line || t.bytes.empty()) return false;
  out = t;
  return true;
}

struct CandumpLine {
  std::string timestamp;
  std::string interface;
  std::uint32_t id = 0;
  std::vector<std::uint8_t> data;
};

/// "(SECONDS.MICROS) IFACE III#DD…": 3 upper-case hex digits, upper-case data, nothing else.
inline bool parse_candump_line(const std::string& line, CandumpLine& out) {
  if (line.empty() || line[0] != '(') return false;
  const auto close = line.find(") ");
  if (close == std::string::npos) return false;
  CandumpLine c;
  c.timestamp = line.substr(1, close - 1);
  const auto space = line.find(' ', close + 2);
  if (!is_timestamp(c.timestamp) || space == std::string::npos) return false;
  c.interface = line.substr(close + 2, space - close - 2);
  const std::string frame = line.substr(space + 1);
  if (c.interface.empty() || frame.size() < 4 || frame[3] != '#') return false;
  const std::string id = frame.substr(0, 3);
  const std::string data = frame.substr(4);
  if (!all_of(id, "0123456789ABCDEF") || data.size() % 2 != 0 || data.size() > 16 ||
      (!data.empty() && !all_of(data, "0123456789ABCDEF"))) {
    return false;
  }
  c.id = static_cast<std::uint32_t>(std::stoul(id, nullptr, 16));
  for (std::size_t i = 0; i < data.size(); i += 2) {
    c.data.push_back(static_cast<std::uint8_t>(std::stoul(data.substr(i, 2), nullptr, 16)));
  }
  out = c;
  return true;
}

}  // namespace cmmcomp::vc::test
