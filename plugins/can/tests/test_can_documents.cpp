// SPDX-License-Identifier: MIT
/// @file One source of truth: the DBC file, the signal table and the worked example of
/// docs/protocol-can.md must say exactly what the codec does.
#include <gtest/gtest.h>

#include <cmmcomp/plugins/can_request_handler.hpp>
#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "can_example_result.hpp"
#include "can_test_frames.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins::can;
using cmmcomp::plugins::CanFrameBatch;
using cmmcomp::plugins::CanRequestHandler;

std::vector<std::string> read_lines(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << "cannot open " << path;
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

std::string trim(const std::string& s) {
  const std::size_t b = s.find_first_not_of(" \t");
  const std::size_t e = s.find_last_not_of(" \t\r");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

/// One SG_ line of the DBC, parsed.
struct DbcSignal {
  std::string name;
  std::int8_t mux = kNotMultiplexed;
  unsigned start = 0, length = 0;
  bool little_endian = false, is_signed = false;
  double factor = 0, offset = 0, min = 0, max = 0;
  std::string unit;
};
struct DbcMessage {
  std::uint32_t id = 0;
  std::string name, sender;
  unsigned dlc = 0;
  std::vector<DbcSignal> signals;
};

// BO_ <id> <name>: <dlc> <sender>
// SG_ <name> [M|mN] : <start>|<length>@<1|0><+|-> (<factor>,<offset>) [<min>|<max>] "<unit>" <rx>
std::vector<DbcMessage> parse_dbc(const std::string& path) {
  std::vector<DbcMessage> messages;
  for (const std::string& raw : read_lines(path)) {
    const std::string line = trim(raw);
    if (line.rfind("BO_ ", 0) == 0) {
      DbcMessage m;
      std::istringstream in(line.substr(4));
      std::string name;
      in >> m.id >> name >> m.dlc >> m.sender;
      EXPECT_FALSE(name.empty() || name.back() != ':') << line;
      m.name = name.substr(0, name.size() - 1);
      messages.push_back(m);
    } else if (line.rfind("SG_ ", 0) == 0) {
      EXPECT_FALSE(messages.empty()) << "SG_ before any BO_: " << line;
      if (messages.empty()) continue;
      DbcSignal s;
      const std::size_t colon = line.find(" : ");
      std::istringstream head(line.substr(4, colon - 4));
      std::string mux;
      head >> s.name >> mux;
      if (mux == "M") {
        s.mux = kMultiplexor;
      } else if (!mux.empty()) {
        EXPECT_EQ(mux[0], 'm') << line;
        s.mux = static_cast<std::int8_t>(std::stoi(mux.substr(1)));
      }
      const std::string body = line.substr(colon + 3);
      char order = 0, sign = 0;
      const int got = std::sscanf(body.c_str(),
                                  "%u|%u@%c%c (%lf,%lf) [%lf|%lf]",
                                  &s.start,
                                  &s.length,
                                  &order,
                                  &sign,
                                  &s.factor,
                                  &s.offset,
                                  &s.min,
                                  &s.max);
      EXPECT_EQ(got, 8) << line;
      s.little_endian = order == '1';
      s.is_signed = sign == '-';
      const std::size_t q1 = body.find('"');
      const std::size_t q2 = body.find('"', q1 + 1);
      EXPECT_NE(q2, std::string::npos) << line;
      s.unit = body.substr(q1 + 1, q2 - q1 - 1);
      messages.back().signals.push_back(s);
    }
  }
  return messages;
}

TEST(CanDbc, DescribesExactlyTheCodecsMessagesAndSignals) {
  const std::vector<DbcMessage> dbc = parse_dbc(CMMCOMP_CAN_DBC);
  ASSERT_EQ(dbc.size(), kMessages.size());
  for (std::size_t i = 0; i < kMessages.size(); ++i) {
    const MessageSpec& code = kMessages[i];
    const DbcMessage& file = dbc[i];
    SCOPED_TRACE(code.name);
    EXPECT_EQ(file.name, code.name);
    EXPECT_EQ(file.id, kDefaultBaseId + code.offset);
    EXPECT_EQ(file.dlc, kFrameDlc);
    EXPECT_EQ(file.sender, code.sender);
    ASSERT_EQ(file.signals.size(), code.signal_count);
    for (std::size_t k = 0; k < code.signal_count; ++k) {
      const SignalSpec& c = code.signals[k];
      const DbcSignal& f = file.signals[k];
      SCOPED_TRACE(c.name);
      EXPECT_EQ(f.name, c.name);
      EXPECT_EQ(f.mux, c.mux);
      EXPECT_EQ(f.start, c.start);
      EXPECT_EQ(f.length, c.length);
      EXPECT_TRUE(f.little_endian);
      EXPECT_EQ(f.is_signed, c.is_signed);
      EXPECT_EQ(f.factor, c.factor);
      EXPECT_EQ(f.offset, c.offset);
      EXPECT_EQ(f.min, c.min);
      EXPECT_EQ(f.max, c.max);
      EXPECT_EQ(f.unit, c.unit);
    }
  }
}

const SignalSpec* find_signal(const std::string& name, const MessageSpec** message) {
  for (const MessageSpec& m : kMessages) {
    for (std::size_t k = 0; k < m.signal_count; ++k) {
      if (name == m.signals[k].name) {
        *message = &m;
        return &m.signals[k];
      }
    }
  }
  return nullptr;
}

std::vector<std::string> cells(const std::string& row) {
  std::vector<std::string> out;
  std::string cell;
  for (std::size_t i = 1; i < row.size(); ++i) {
    if (row[i] == '|') {
      out.push_back(trim(cell));
      cell.clear();
    } else {
      cell += row[i];
    }
  }
  return out;
}

std::string strip_ticks(const std::string& s) {
  std::string out;
  for (char c : s) {
    if (c != '`') out += c;
  }
  return out;
}

// Rows of the document's signal table:
// | message | signal | part | bits (start, length) | type | factor | offset | min | max | unit |
TEST(CanProtocolDoc, SignalTableListsEverySignalAsTheCodecDefinesIt) {
  std::map<std::string, int> seen;
  for (const std::string& line : read_lines(CMMCOMP_CAN_DOC)) {
    if (line.rfind("| ", 0) != 0) continue;
    const std::vector<std::string> c = cells(line);
    if (c.size() != 10) continue;
    const std::string name = strip_ticks(c[1]);
    const MessageSpec* m = nullptr;
    const SignalSpec* s = find_signal(name, &m);
    if (s == nullptr) continue;  // header or another table
    SCOPED_TRACE(line);
    ++seen[name];
    EXPECT_EQ(c[0], m->name);
    const std::string part = s->mux == kMultiplexor      ? "mux"
                             : s->mux == kNotMultiplexed ? "all"
                                                         : std::to_string(s->mux);
    EXPECT_EQ(c[2], part);
    EXPECT_EQ(c[3], std::to_string(s->start) + ", " + std::to_string(s->length));
    EXPECT_EQ(c[4], s->is_signed ? "signed" : "unsigned");
    EXPECT_EQ(std::stod(c[5]), s->factor);
    EXPECT_EQ(std::stod(c[6]), s->offset);
    EXPECT_EQ(std::stod(c[7]), s->min);
    EXPECT_EQ(std::stod(c[8]), s->max);
    const std::string unit = c[9] == "µm"      ? "um"
                             : c[9] == "mm/s²" ? "mm/s2"
                             : c[9] == "–"     ? ""
                                               : c[9];
    EXPECT_EQ(unit, s->unit);
  }
  for (const MessageSpec& m : kMessages) {
    for (std::size_t k = 0; k < m.signal_count; ++k) {
      EXPECT_EQ(seen[m.signals[k].name], 1) << m.signals[k].name << " in the document's table";
    }
  }
}

/// The fenced block after the line `<!-- marker -->`, one string per line.
std::vector<std::string> example_block(const std::string& marker) {
  const std::vector<std::string> lines = read_lines(CMMCOMP_CAN_DOC);
  std::vector<std::string> block;
  bool after_marker = false, inside = false;
  for (const std::string& line : lines) {
    if (!after_marker) {
      after_marker = line == "<!-- " + marker + " -->";
    } else if (line.rfind("```", 0) == 0) {
      if (inside) break;
      inside = true;
    } else if (inside) {
      block.push_back(line);
    }
  }
  EXPECT_FALSE(block.empty()) << "no block after <!-- " << marker << " --> in the document";
  return block;
}

/// The `cansend` frames of the block after <!-- request_marker --> and the `candump -L` frames
/// (timestamps aside) of the block after <!-- response_marker -->.
void example_frames(const std::string& request_marker,
                    const std::string& response_marker,
                    std::vector<Frame>& sent,
                    std::vector<std::string>& expected) {
  for (const std::string& line : example_block(request_marker)) {
    std::istringstream in(line);
    std::string tool, interface, frame;
    in >> tool >> interface >> frame;
    ASSERT_EQ(tool, "cansend") << line;
    Frame f;
    ASSERT_TRUE(cmmcomp::test::from_text(frame, f)) << line;
    sent.push_back(f);
  }
  for (const std::string& line : example_block(response_marker)) {
    std::istringstream in(line);
    std::string stamp, interface, frame;
    in >> stamp >> interface >> frame;
    ASSERT_EQ(stamp.front(), '(') << "candump -L line expected: " << line;
    expected.push_back(frame);
  }
}

/// What the server's handler answers to `sent` (one frame a millisecond), as candump text.
std::vector<std::string> answer_of(const std::vector<Frame>& sent, CanFrameBatch& out) {
  compensation::MoveCompensator comp;
  EXPECT_EQ(cmmcomp::test::publish_example(comp), Status::kOk);
  CanRequestHandler handler(comp, kDefaultBaseId, std::chrono::milliseconds(50));
  std::int64_t t = 0;
  for (const Frame& f : sent) handler.on_frame(f, t += 1'000'000, out);
  std::vector<std::string> got;
  for (std::size_t i = 0; i < out.size; ++i) got.push_back(cmmcomp::test::to_text(out.frames[i]));
  return got;
}

// The worked example: `cansend` lines in, `candump -L` lines out (timestamps aside), through
// the same handler the server runs, with the closed-form model. A version-1 request
// (WantInterval 0): the three frames of protocol version 1, byte for byte.
TEST(CanProtocolDoc, WorkedExampleIsWhatTheServerAnswers) {
  std::vector<Frame> sent;
  std::vector<std::string> expected;
  example_frames("example:request", "example:response", sent, expected);
  // The document's request is the example move, encoded.
  RequestFrames encoded;
  ASSERT_EQ(encode_request(cmmcomp::test::example_move(), kDefaultBaseId, encoded), Status::kOk);
  ASSERT_EQ(sent.size(), kRequestParts);
  for (std::size_t p = 0; p < kRequestParts; ++p) {
    EXPECT_EQ(cmmcomp::test::to_text(sent[p]), cmmcomp::test::to_text(encoded[p]));
  }
  CanFrameBatch out;
  EXPECT_EQ(answer_of(sent, out), expected);
  // ... and it says what the document says in words: MPE 3.5, RPE −1, MAE 4, RAE 3.5 µm,
  // correction (−3.5, 0, 0) µm, flags OK, model id 0xC0FFEE01, sequence 5.
  ASSERT_EQ(out.size, kResponseParts);
  DecodedResponse d;
  ASSERT_TRUE(decode_response({out.frames[0], out.frames[1], out.frames[2]}, kDefaultBaseId, d));
  cmmcomp::test::expect_example_response(d);
}

// The second worked example: the same move (sequence 6) with WantInterval gets the same three
// frames and part 3, the interval of the calibrated example model.
TEST(CanProtocolDoc, WorkedIntervalExampleIsWhatTheServerAnswers) {
  std::vector<Frame> sent;
  std::vector<std::string> expected;
  example_frames("example:interval-request", "example:interval-response", sent, expected);
  RequestFrames encoded;
  ASSERT_EQ(encode_request(cmmcomp::test::example_interval_move(),
                           kDefaultBaseId,
                           encoded,
                           nullptr,
                           /*want_interval=*/true),
            Status::kOk);
  ASSERT_EQ(sent.size(), kRequestParts);
  for (std::size_t p = 0; p < kRequestParts; ++p) {
    EXPECT_EQ(cmmcomp::test::to_text(sent[p]), cmmcomp::test::to_text(encoded[p]));
  }
  CanFrameBatch out;
  EXPECT_EQ(answer_of(sent, out), expected);
  ASSERT_EQ(out.size, kResponseParts + 1u);
  DecodedResponse d;
  ASSERT_TRUE(decode_response({out.frames[0], out.frames[1], out.frames[2]}, kDefaultBaseId, d));
  ASSERT_TRUE(decode_interval(out.frames[3], kDefaultBaseId, d));
  cmmcomp::test::expect_example_interval_response(d);
  // Parts 0–2 differ from the first example's only in the sequence.
  std::vector<Frame> v1_sent;
  std::vector<std::string> v1_expected;
  example_frames("example:request", "example:response", v1_sent, v1_expected);
  ASSERT_EQ(v1_expected.size(), kResponseParts);
  for (std::size_t p = 0; p < kResponseParts; ++p) {
    EXPECT_EQ(expected[p].substr(6), v1_expected[p].substr(6)) << "part " << p;
  }
}

// The document's reject examples (| sent | answer | why |), in order, through one handler.
TEST(CanProtocolDoc, RejectExamplesAreWhatTheServerAnswers) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(cmmcomp::test::publish_example(comp), Status::kOk);
  CanRequestHandler handler(comp, kDefaultBaseId, std::chrono::milliseconds(50));
  RequestFrames example;
  ASSERT_EQ(encode_request(cmmcomp::test::example_move(), kDefaultBaseId, example), Status::kOk);
  const auto between_ticks = [](const std::string& s) {
    const std::size_t a = s.find('`');
    const std::size_t b = s.find('`', a + 1);
    return a == std::string::npos || b == std::string::npos ? std::string()
                                                            : s.substr(a + 1, b - a - 1);
  };
  std::int64_t t = 0;
  int rows = 0;
  for (const std::string& line : read_lines(CMMCOMP_CAN_DOC)) {
    if (line.rfind("| `300#", 0) != 0 && line.rfind("| part 0 alone", 0) != 0) continue;
    const std::vector<std::string> c = cells(line);
    ASSERT_EQ(c.size(), 3u) << line;
    SCOPED_TRACE(line);
    ++rows;
    CanFrameBatch out;
    t += 1'000'000'000;  // rows are independent: far apart in time
    if (c[0].rfind("part 0 alone", 0) == 0) {
      handler.on_frame(example[0], t, out);
      ASSERT_EQ(out.size, 0u);
      handler.on_time(t + 50'000'000, out);  // the part timeout has passed
    } else {
      Frame sent;
      ASSERT_TRUE(cmmcomp::test::from_text(between_ticks(c[0]), sent));
      handler.on_frame(sent, t, out);
      if (c[0].find("then parts 1 and 2") != std::string::npos) {  // checked when complete
        ASSERT_EQ(out.size, 0u);
        handler.on_frame(example[1], t + 1'000'000, out);
        handler.on_frame(example[2], t + 2'000'000, out);
      }
    }
    ASSERT_EQ(out.size, 1u);
    EXPECT_EQ(cmmcomp::test::to_text(out.frames[0]), between_ticks(c[1]));
  }
  EXPECT_EQ(rows, 5);
}

}  // namespace
