// SPDX-License-Identifier: MIT
/// @file The recording parsers (docs/recordings.md): good lines, comments, and malformed lines
/// reported with file:line; and the decoders that name the field of a differing byte.
#include <gtest/gtest.h>

#include <sstream>
#include <string>

#include "can_decode.hpp"
#include "modbus_decode.hpp"
#include "recording.hpp"

namespace {

using cmmcomp::replay::FieldValue;
using cmmcomp::replay::Recording;
using cmmcomp::replay::RecordingError;
using cmmcomp::replay::RecordingFormat;

// The first point of the default run, as docs/recordings.md shows it.
const char* const kTx =
    "1795396532.842412 tx 00 01 00 00 00 3d 01 17 00 19 00 17 00 00 00 19 32 00 00 00 00 bf 80 "
    "00 00 00 00 00 00 00 00 00 00 42 c8 00 00 43 48 00 00 42 70 00 00 41 80 00 00 42 70 00 00 "
    "41 20 00 00 00 00 00 00 00 00 00 00 00 01";
const char* const kRx =
    "1795396532.842525 rx 00 01 00 00 00 31 01 17 2e 00 01 00 00 00 01 00 00 00 00 42 02 f2 31 "
    "c1 de b5 07 41 04 37 14 c0 a9 86 17 40 a9 86 17 80 00 00 00 80 00 00 00 c2 fc 35 06 91 49 "
    "ab 07";

Recording transcript(const std::string& text) {
  std::istringstream in(text);
  return cmmcomp::replay::parse_modbus_transcript(in, "s.mbtx");
}

Recording candump(const std::string& text) {
  std::istringstream in(text);
  return cmmcomp::replay::parse_candump_log(in, "s.log");
}

/// The message of the RecordingError `f` throws ("" when it does not throw).
template <typename F>
std::string error_of(F f) {
  try {
    f();
  } catch (const RecordingError& e) {
    return e.what();
  }
  return "";
}

TEST(ModbusTranscript, ReadsRequestsAndAnswersAndSkipsComments) {
  const Recording r = transcript(std::string("# cmmcomp modbus transcript 1\n# agent agent\n") +
                                 kTx + "\n# a comment the reader does not know\n\n" + kRx + "\n");
  EXPECT_EQ(r.format, RecordingFormat::kModbusTranscript);
  ASSERT_EQ(r.messages.size(), 2u);
  EXPECT_TRUE(r.messages[0].from_controller);
  EXPECT_FALSE(r.messages[1].from_controller);
  EXPECT_EQ(r.messages[0].line, 3);
  EXPECT_EQ(r.messages[1].line, 6);
  EXPECT_EQ(r.messages[0].time_us, 1795396532842412);
  EXPECT_EQ(r.messages[0].bytes.size(), 67u);
  EXPECT_EQ(r.messages[1].bytes.back(), 0x07);
  EXPECT_EQ(r.comments, 4);
}

TEST(ModbusTranscript, MalformedLinesNameFileLineAndProblem) {
  const std::string head = "# cmmcomp modbus transcript 1\n";
  EXPECT_EQ(error_of([] { transcript("# cmmcomp modbus transcript 2\n"); }),
            "s.mbtx:1: transcript version '2' is not supported (this reader knows version 1)");
  EXPECT_EQ(error_of([] { transcript("1.000000 tx 00\n"); }),
            "s.mbtx:1: the first line must be '# cmmcomp modbus transcript 1'");
  EXPECT_EQ(
      error_of([&] { transcript(head + "# x\n1795396532.84241 tx 00 01 00 00 00 02 01 03\n"); }),
      "s.mbtx:3: timestamp '1795396532.84241' is not SECONDS.MICROS (6 digits after the point, at "
      "most 9223372036.854775)");
  EXPECT_EQ(error_of([&] { transcript(head + "1.000000 up 00 01 00 00 00 02 01 03\n"); }),
            "s.mbtx:2: direction 'up' is neither tx nor rx");
  EXPECT_EQ(error_of([&] { transcript(head + "1.000000 tx 00 01 00 00 00 02 01 0A\n"); }),
            "s.mbtx:2: byte 7 '0A' is not two lower-case hex digits");
  EXPECT_EQ(error_of([&] { transcript(head + "1.000000 tx 00 01 00 00 00 05 01 03\n"); }),
            "s.mbtx:2: MBAP length 5 says 11 bytes, the line has 8");
  EXPECT_EQ(error_of([&] { transcript(head + "1.000000 tx 00 01 00\n"); }),
            "s.mbtx:2: an ADU has at least 8 bytes (MBAP header and function code), this line "
            "has 3");
  EXPECT_EQ(error_of([&] { transcript(head + "1.000000 tx\n"); }),
            "s.mbtx:2: expected 'SECONDS.MICROS tx|rx XX XX …', got '1.000000 tx'");
  EXPECT_EQ(error_of([&] { transcript(head + "1.000000 tx  00 01 00 00 00 02 01 03\n"); }),
            "s.mbtx:2: byte 0 '' is not two lower-case hex digits");
}

// Issue 16 D8: a time that int64 nanoseconds cannot hold used to overflow in replay (a false
// timeout reject); the parsers refuse it, and accept the last representable microsecond.
TEST(Recordings, RefuseTimesBeyondTheNanosecondRange) {
  const std::string head = "# cmmcomp modbus transcript 1\n";
  const std::string adu = " tx 00 01 00 00 00 02 01 03\n";
  EXPECT_EQ(transcript(head + "9223372036.854775" + adu).messages.at(0).time_us, 9223372036854775);
  EXPECT_EQ(error_of([&] { transcript(head + "9223372036.854776" + adu); }),
            "s.mbtx:2: timestamp '9223372036.854776' is not SECONDS.MICROS (6 digits after the "
            "point, at most 9223372036.854775)");
  EXPECT_EQ(error_of([&] { transcript(head + "99999999999.000000" + adu); }),
            "s.mbtx:2: timestamp '99999999999.000000' is not SECONDS.MICROS (6 digits after the "
            "point, at most 9223372036.854775)");
  EXPECT_EQ(candump("(9223372036.854775) vcan0 300#00\n").messages.at(0).time_us, 9223372036854775);
  EXPECT_NE(error_of([] { candump("(9999999999.000000) vcan0 300#00\n"); }), "");
}

TEST(CandumpLog, ReadsFramesAndSkipsComments) {
  const Recording r = candump(
      "(1795396714.094314) vcan0 300#00E8037017400600\n# note\n\n"
      "(1795396714.095207) vcan1 301#0001ca0c20f53a03\n(1795396714.095300) vcan0 303#\n");
  EXPECT_EQ(r.format, RecordingFormat::kCandumpLog);
  ASSERT_EQ(r.messages.size(), 3u);
  EXPECT_EQ(r.messages[0].can_id, 0x300u);
  EXPECT_EQ(r.messages[0].interface, "vcan0");
  EXPECT_EQ(r.messages[0].bytes.size(), 8u);
  EXPECT_EQ(r.messages[0].bytes[1], 0xE8);
  EXPECT_EQ(r.messages[1].line, 4);
  EXPECT_EQ(r.messages[1].interface, "vcan1");
  EXPECT_EQ(r.messages[1].bytes[2], 0xCA);  // lower case accepted as candump reads it
  EXPECT_TRUE(r.messages[2].bytes.empty());
  EXPECT_EQ(r.comments, 2);
}

TEST(CandumpLog, MalformedLinesNameFileLineAndProblem) {
  const std::string good = "(1.000000) vcan0 300#00\n";
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 12345678#00\n"); }),
            "s.log:2: extended identifier '12345678': the protocol uses 11-bit ids");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 800#00\n"); }),
            "s.log:2: identifier '800' is above 0x7FF");
  EXPECT_EQ(error_of([&] { candump(good + good + "(1.000000) vcan0 30G#00\n"); }),
            "s.log:3: identifier '30G' is not hexadecimal");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 300-00\n"); }),
            "s.log:2: frame '300-00' has no '#' (ID#DATA)");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 300#001\n"); }),
            "s.log:2: data '001' is not 0 to 8 bytes of two hex digits each");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 300#0011223344556677889\n"); }),
            "s.log:2: data '0011223344556677889' is not 0 to 8 bytes of two hex digits each");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 300#R\n"); }),
            "s.log:2: remote or CAN FD frame '300#R': the protocol uses classic data frames");
  EXPECT_EQ(error_of([&] { candump(good + "(1.0) vcan0 300#00\n"); }),
            "s.log:2: timestamp '(1.0)' is not (SECONDS.MICROS) with 6 digits after the point, at "
            "most 9223372036.854775");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0\n"); }),
            "s.log:2: expected '(SECONDS.MICROS) IFACE ID#DATA', got '(1.000000) vcan0'");
  EXPECT_EQ(error_of([&] { candump(good + "(1.000000) vcan0 300#ZZ\n"); }),
            "s.log:2: data 'ZZ' is not hexadecimal");
}

TEST(RecordingFormat, DetectedFromTheFirstLine) {
  EXPECT_EQ(cmmcomp::replay::detect_format("# cmmcomp modbus transcript 1", "f"),
            RecordingFormat::kModbusTranscript);
  EXPECT_EQ(cmmcomp::replay::detect_format("(1.000000) vcan0 300#00", "f"),
            RecordingFormat::kCandumpLog);
  EXPECT_EQ(error_of([] {
              cmmcomp::replay::detect_format("hello", "f");
            }).rfind("f:1: not a recording", 0),
            0u);
  EXPECT_EQ(error_of([] { cmmcomp::replay::load_recording("/nonexistent/session.log"); }),
            "/nonexistent/session.log: cannot open the file");
}

const FieldValue* field(const std::vector<FieldValue>& fields, std::size_t offset) {
  return cmmcomp::replay::field_at(fields, offset);
}

TEST(ModbusDecode, NamesEveryByteOfTheDocumentedAnswer) {
  const Recording r = transcript(std::string("# cmmcomp modbus transcript 1\n") + kTx + "\n" + kRx);
  const auto fields =
      cmmcomp::replay::decode_modbus_answer(r.messages[0].bytes, r.messages[1].bytes);
  ASSERT_NE(field(fields, 0), nullptr);
  EXPECT_EQ(field(fields, 1)->name, "transaction id");
  EXPECT_EQ(field(fields, 9)->name, "sequence");
  EXPECT_EQ(field(fields, 11)->value, "0 (ok)");
  EXPECT_EQ(field(fields, 31)->name, "RAE");
  EXPECT_EQ(field(fields, 34)->value, "-5.298 µm");
  EXPECT_EQ(field(fields, 35)->name, "correction x");
  EXPECT_EQ(field(fields, 50)->name, "model id");
  EXPECT_EQ(field(fields, 54)->value, "c2fc35069149ab07");
  EXPECT_EQ(cmmcomp::replay::summarize_modbus_request(r.messages[0].bytes),
            "FC17 seq 1 axis 0 dir (-1, 0, 0) PV 100 PD 60 AV 16 AD 10 Y 0");
}

TEST(CanDecode, NamesTheSignalsOfAResponsePart) {
  const Recording r = candump("(1.000000) vcan0 301#01EEFD1202000000\n");
  const auto fields = cmmcomp::replay::decode_can_frame(0x300, 0x301, r.messages[0].bytes);
  ASSERT_NE(field(fields, 1), nullptr);
  EXPECT_EQ(field(fields, 1)->name, "RAE");
  EXPECT_EQ(field(fields, 2)->value, "-5.3 µm");
  EXPECT_EQ(field(fields, 3)->name, "CorrX");
  EXPECT_EQ(field(fields, 4)->value, "5.3 µm");
  EXPECT_EQ(cmmcomp::replay::format_can_frame(0x301, r.messages[0].bytes), "301#01EEFD1202000000");
  EXPECT_TRUE(cmmcomp::replay::decode_can_frame(0x300, 0x123, r.messages[0].bytes).empty());
}

// Protocol version 2: response part 3 (docs/protocol-can.md's second worked example) and the
// request's WantInterval, by name; the answer's summary adds U95 of RAE and any interval flag.
TEST(CanDecode, NamesTheSignalsOfTheIntervalPart) {
  const Recording r = candump(
      "(1.000000) vcan0 301#1B0089C006412002\n(1.000001) vcan0 301#1B03000000000000\n"
      "(1.000002) vcan0 300#18A901A00F200310\n");
  const auto fields = cmmcomp::replay::decode_can_frame(0x300, 0x301, r.messages[0].bytes);
  ASSERT_NE(field(fields, 1), nullptr);
  EXPECT_EQ(field(fields, 1)->name, "IntervalFlags");
  EXPECT_EQ(field(fields, 1)->value, "0");
  EXPECT_EQ(field(fields, 2)->name, "U95MPE");
  EXPECT_EQ(field(fields, 2)->value, "2.74 µm");
  EXPECT_EQ(field(fields, 4)->name, "U95RPE");
  EXPECT_EQ(field(fields, 4)->value, "2.16 µm");
  EXPECT_EQ(field(fields, 7)->name, "U95RAE");
  EXPECT_EQ(field(fields, 7)->value, "0.68 µm");
  EXPECT_EQ(cmmcomp::replay::summarize_can_answer(0x300, {0x301}, {r.messages[0].bytes}),
            "U95 RAE 0.68 µm");
  const auto flagged = cmmcomp::replay::decode_can_frame(0x300, 0x301, r.messages[1].bytes);
  EXPECT_EQ(field(flagged, 1)->value, "3 (NO_UNCERTAINTY SATURATED)");
  EXPECT_EQ(cmmcomp::replay::summarize_can_answer(0x300, {0x301}, {r.messages[1].bytes}),
            "U95 RAE 0 µm interval flags 3 (NO_UNCERTAINTY SATURATED)");
  const auto request = cmmcomp::replay::decode_can_frame(0x300, 0x300, r.messages[2].bytes);
  const FieldValue* want = cmmcomp::replay::field_named(request, "WantInterval");
  ASSERT_NE(want, nullptr);
  EXPECT_EQ(want->value, "1");
  EXPECT_EQ(want->begin, 7u);
}

}  // namespace
