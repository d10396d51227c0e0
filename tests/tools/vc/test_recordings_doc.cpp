// SPDX-License-Identifier: MIT
/// @file docs/recordings.md against the code: its example lines have exactly the documented
/// form, the transcript header is what the vc writes, and the example frames and registers
/// decode to the values the document states.
#include <gtest/gtest.h>

#include <cmmcomp/plugins/can_protocol.hpp>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "line_forms.hpp"
#include "recording_format.hpp"

#ifndef CMMCOMP_RECORDINGS_DOC
#error "CMMCOMP_RECORDINGS_DOC must name docs/recordings.md"
#endif
#ifndef CMMCOMP_RECORDINGS_DIR
#error "CMMCOMP_RECORDINGS_DIR must name tests/tools/replay/data"
#endif

namespace cmmcomp::vc {
namespace {

/// Lines of the ```text blocks of the document.
std::vector<std::string> example_lines() {
  std::ifstream in(CMMCOMP_RECORDINGS_DOC);
  std::vector<std::string> out;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("```", 0) == 0) {
      inside = line == "```text";
      continue;
    }
    if (inside) out.push_back(line);
  }
  return out;
}

TEST(RecordingsDoc, TranscriptExampleHasTheDocumentedForm) {
  std::string header;
  std::vector<std::vector<std::uint8_t>> adus;
  for (const auto& l : example_lines()) {
    if (l.rfind("# ", 0) == 0) {
      header += l + "\n";
      continue;
    }
    test::TranscriptLine t;
    if (test::parse_transcript_line(l, t)) adus.push_back(t.bytes);
  }
  EXPECT_EQ(header, modbus_transcript_header("agent", 1));
  ASSERT_EQ(adus.size(), 2u);
  for (const auto& a : adus) {
    ASSERT_GE(a.size(), 8u);
    EXPECT_EQ(a.size(), 6u + ((std::size_t{a[4]} << 8) | a[5])) << "MBAP length";
  }
  // The request registers start at byte 17 (after MBAP, FC23's four addresses and byte count).
  plugins::modbus::HoldingRegisters h{};
  for (std::size_t i = 0; i < plugins::modbus::kRequestCount; ++i) {
    h[i] = static_cast<std::uint16_t>((adus[0][17 + 2 * i] << 8) | adus[0][18 + 2 * i]);
  }
  compensation::MoveRequest m;
  ASSERT_EQ(plugins::modbus::decode_request(h, m), Status::kOk);
  EXPECT_EQ(m.direction[0], -1.0);
  EXPECT_EQ(m.pv_mm_s, 100.0);
  EXPECT_EQ(m.ad_mm, 10.0);
  EXPECT_EQ(m.sequence, 1u);
  // The answer: holding 25-47 (the result block), then 48-57 (the interval block).
  namespace map = plugins::modbus;
  ASSERT_EQ(adus[1].size(), 9u + 2u * (map::kResultWords + map::kIntervalWords));
  map::InputRegisters in{};
  for (std::size_t i = 0; i < map::kResultWords + map::kIntervalWords; ++i) {
    const std::size_t reg = i < map::kResultWords ? map::kResultSequence + i
                                                  : map::kIntervalFlags + (i - map::kResultWords);
    in[reg] = static_cast<std::uint16_t>((adus[1][9 + 2 * i] << 8) | adus[1][10 + 2 * i]);
  }
  const auto r = map::decode_result(in);
  EXPECT_EQ(r.sequence, 1u);
  EXPECT_NEAR(r.rae_um, -4.773, 5e-4);
  EXPECT_NEAR(r.correction_um[0], 4.773, 5e-4);
  EXPECT_EQ(r.model_id, 0x2a3dd67687400fa5ull);
  EXPECT_EQ(r.interval_flags, compensation::kFlagOk);
  EXPECT_NEAR(r.u95_um[0], 2.735, 5e-4);
  EXPECT_NEAR(r.u95_um[1], 1.858, 5e-4);
  EXPECT_NEAR(r.u95_um[3], 0.680, 5e-4);
}

TEST(RecordingsDoc, CandumpExampleHasTheDocumentedFormAndDecodes) {
  std::vector<plugins::can::Frame> frames;
  for (const auto& l : example_lines()) {
    test::CandumpLine c;
    if (!test::parse_candump_line(l, c)) continue;
    ASSERT_EQ(c.interface, "vcan0");
    ASSERT_EQ(c.data.size(), 8u);
    plugins::can::Frame f;
    f.id = c.id;
    f.dlc = 8;
    for (std::size_t i = 0; i < 8; ++i) f.data[i] = c.data[i];
    // The writer produces exactly this line back.
    const auto dot = c.timestamp.find('.');
    const std::int64_t us =
        std::stoll(c.timestamp.substr(0, dot)) * 1000000 + std::stoll(c.timestamp.substr(dot + 1));
    EXPECT_EQ(candump_line(us, "vcan0", f), l + "\n");
    frames.push_back(f);
  }
  // Three request frames (WantInterval set), four response frames (CAN protocol version 2).
  ASSERT_EQ(frames.size(), 7u);
  EXPECT_EQ(plugins::can::get_raw(plugins::can::load_word(frames[0]),
                                  plugins::can::request::kWantInterval),
            1);
  plugins::can::ResponseFrames resp{frames[3], frames[4], frames[5]};
  plugins::can::DecodedResponse d;
  ASSERT_TRUE(plugins::can::decode_response(resp, 0x300, d));
  ASSERT_TRUE(plugins::can::decode_interval(frames[6], 0x300, d));
  EXPECT_NEAR(d.correction.mpe_um, 21.58, 1e-9);
  EXPECT_NEAR(d.correction.rae_um, -4.77, 1e-9);
  EXPECT_NEAR(d.correction.correction_um[0], 4.77, 1e-9);
  EXPECT_EQ(d.correction.model_id, 0x87400FA5u);
  EXPECT_EQ(d.interval_flags, 0);
  EXPECT_NEAR(d.correction.u95_um[0], 2.74, 1e-9);
  EXPECT_NEAR(d.correction.u95_um[1], 1.86, 1e-9);
  EXPECT_NEAR(d.correction.u95_um[2], 1.32, 1e-9);
  EXPECT_NEAR(d.correction.u95_um[3], 0.68, 1e-9);
}

/// The lines of `path` that are not comments.
std::vector<std::string> data_lines(const std::string& path) {
  std::ifstream in(path);
  std::vector<std::string> out;
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] != '#') out.push_back(line);
  }
  return out;
}

// The examples are the first exchange of the committed recordings of the shipped 4-input model
// (scripts/regenerate-recordings.sh), timestamps included: when the model or the recordings are
// regenerated, the document must follow.
TEST(RecordingsDoc, ExamplesAreTheCommittedRecordingsFirstExchange) {
  std::vector<std::string> transcript, candump;
  for (const auto& l : example_lines()) {
    test::TranscriptLine t;
    test::CandumpLine c;
    if (test::parse_transcript_line(l, t)) transcript.push_back(l);
    if (test::parse_candump_line(l, c)) candump.push_back(l);
  }
  const auto modbus = data_lines(std::string(CMMCOMP_RECORDINGS_DIR) + "/modbus-default.log");
  const auto can = data_lines(std::string(CMMCOMP_RECORDINGS_DIR) + "/can-default.log");
  ASSERT_EQ(transcript.size(), 2u);
  ASSERT_EQ(candump.size(), 7u);
  ASSERT_GE(modbus.size(), transcript.size());
  ASSERT_GE(can.size(), candump.size());
  for (std::size_t i = 0; i < transcript.size(); ++i) EXPECT_EQ(transcript[i], modbus[i]) << i;
  for (std::size_t i = 0; i < candump.size(); ++i) EXPECT_EQ(candump[i], can[i]) << i;
}

}  // namespace
}  // namespace cmmcomp::vc
