// SPDX-License-Identifier: MIT
/// @file The recording formats exactly as docs/recordings.md shows them, the MBAP splitter, the
/// recording relay against a loopback echo peer, and the command-line agent specifications.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmmcomp/exceptions.hpp>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "agent_spec.hpp"
#include "correction_source.hpp"
#include "line_forms.hpp"
#include "modbus_relay.hpp"
#include "recording_format.hpp"

namespace cmmcomp::vc {
namespace {

TEST(RecordingFormat, TimestampHasSixDigitsOfMicroseconds) {
  EXPECT_EQ(format_timestamp(1700000000000100), "1700000000.000100");
  EXPECT_EQ(format_timestamp(1700000000999999), "1700000000.999999");
  EXPECT_EQ(format_timestamp(5), "0.000005");
}

TEST(RecordingFormat, ModbusLineIsTimeDirectionAndLowerCaseHex) {
  const std::uint8_t adu[] = {
      0x00, 0x01, 0x00, 0x00, 0x00, 0x06, 0x01, 0x10, 0x00, 0x00, 0x00, 0x19};
  EXPECT_EQ(modbus_transcript_line(1700000000000100, WireDirection::kRx, adu, sizeof adu),
            "1700000000.000100 rx 00 01 00 00 00 06 01 10 00 00 00 19\n");
  EXPECT_EQ(modbus_transcript_line(1700000000000100, WireDirection::kTx, adu, 2),
            "1700000000.000100 tx 00 01\n");
}

TEST(RecordingFormat, ModbusHeaderIsCommentsWithoutTimeOrPort) {
  EXPECT_EQ(modbus_transcript_header("4in", 1),
            "# cmmcomp modbus transcript 1\n# agent 4in\n# transport tcp\n# unit 1\n"
            "# columns: seconds.micros tx|rx adu-hex\n");
}

TEST(RecordingFormat, CandumpLineMatchesCandumpLogFormat) {
  // The response part 0 of docs/protocol-can.md's worked example.
  plugins::can::Frame f;
  f.id = 0x301;
  f.dlc = 8;
  f.data = {0x14, 0x01, 0x5E, 0x01, 0x9C, 0xFF, 0x90, 0x01};
  EXPECT_EQ(candump_line(1700000000000100, "vcan0", f),
            "(1700000000.000100) vcan0 301#14015E019CFF9001\n");
  f.id = 0x05;
  f.dlc = 2;
  EXPECT_EQ(candump_line(1, "can1", f), "(0.000001) can1 005#1401\n");
  f.dlc = 0;
  EXPECT_EQ(candump_line(1, "vcan0", f), "(0.000001) vcan0 005#\n");
}

TEST(MbapSplitter, SplitsByLengthAcrossPartialReads) {
  const std::vector<std::uint8_t> a = {0, 1, 0, 0, 0, 3, 1, 4, 9};
  const std::vector<std::uint8_t> b = {0, 2, 0, 0, 0, 2, 1, 3};
  std::vector<std::uint8_t> stream = a;
  stream.insert(stream.end(), b.begin(), b.end());
  MbapSplitter s;
  auto out = s.feed(stream.data(), 4);
  EXPECT_TRUE(out.empty());
  out = s.feed(stream.data() + 4, 7);  // a complete, 2 bytes of b
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], a);
  EXPECT_EQ(s.pending(), 2u);
  out = s.feed(stream.data() + 11, stream.size() - 11);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(out[0], b);
  EXPECT_EQ(s.pending(), 0u);
}

/// A TCP peer on loopback that answers every chunk with the same bytes.
class EchoPeer {
 public:
  EchoPeer() {
    fd_ = ::socket(AF_INET, SOCK_STREAM, 0);
    sockaddr_in addr{};
    addr.sin_family = AF_INET;
    addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof addr;
    auto* sa = reinterpret_cast<sockaddr*>(&addr);
    EXPECT_EQ(::bind(fd_, sa, sizeof addr), 0);
    EXPECT_EQ(::listen(fd_, 1), 0);
    EXPECT_EQ(::getsockname(fd_, sa, &len), 0);
    port_ = ntohs(addr.sin_port);
    thread_ = std::thread([this] {
      const int c = ::accept(fd_, nullptr, nullptr);
      char buf[512];
      for (;;) {
        const ssize_t n = ::recv(c, buf, sizeof buf, 0);
        if (n <= 0) break;
        if (::send(c, buf, static_cast<std::size_t>(n), MSG_NOSIGNAL) != n) break;
      }
      ::close(c);
    });
  }
  ~EchoPeer() {
    thread_.join();
    ::close(fd_);
  }
  int port() const { return port_; }

 private:
  int fd_ = -1;
  int port_ = 0;
  std::thread thread_;
};

int connect_loopback(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  addr.sin_port = htons(static_cast<std::uint16_t>(port));
  EXPECT_EQ(::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  return fd;
}

TEST(ModbusRecordingRelay, ForwardsBytesAndRecordsEachAduOnce) {
  const std::string path = ::testing::TempDir() + "relay_transcript.txt";
  {
    EchoPeer peer;
    ModbusRecordingRelay relay("127.0.0.1", peer.port(), path, "# test\n");
    const int c = connect_loopback(relay.port());
    const std::uint8_t adu[] = {0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x01, 0x04, 0xff};
    for (int i = 0; i < 2; ++i) {
      // Sent in two pieces: the transcript must still hold one line per ADU.
      ASSERT_EQ(::send(c, adu, 4, 0), 4);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      ASSERT_EQ(::send(c, adu + 4, sizeof adu - 4, 0), static_cast<ssize_t>(sizeof adu - 4));
      std::uint8_t back[sizeof adu];
      std::size_t got = 0;
      while (got < sizeof back) {
        const ssize_t n = ::recv(c, back + got, sizeof back - got, 0);
        ASSERT_GT(n, 0);
        got += static_cast<std::size_t>(n);
      }
      EXPECT_EQ(std::vector<std::uint8_t>(back, back + got),
                std::vector<std::uint8_t>(adu, adu + sizeof adu));
    }
    ::close(c);
  }
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> lines;
  while (std::getline(in, line)) lines.push_back(line);
  ASSERT_EQ(lines.size(), 5u);
  EXPECT_EQ(lines[0], "# test");
  const std::vector<std::uint8_t> want = {0x00, 0x07, 0x00, 0x00, 0x00, 0x03, 0x01, 0x04, 0xff};
  for (std::size_t i = 1; i < 5; ++i) {
    test::TranscriptLine t;
    ASSERT_TRUE(test::parse_transcript_line(lines[i], t)) << lines[i];
    EXPECT_EQ(t.direction, i % 2 == 1 ? "tx" : "rx") << lines[i];
    EXPECT_EQ(t.bytes, want) << lines[i];
  }
}

TEST(ModbusRecordingRelay, UnreachableAgentIsReportedAsSuch) {
  // Port 1 on loopback: nothing listens there in a test environment.
  EXPECT_THROW(ModbusRecordingRelay("127.0.0.1", 1, ::testing::TempDir() + "x.txt", ""),
               UnreachableError);
}

TEST(AgentSpec, ParsesModbusAndCanForms) {
  AgentSpec m = parse_agent_spec("4in=modbus:tcp:127.0.0.1:1502");
  EXPECT_EQ(m.label, "4in");
  EXPECT_FALSE(m.is_can);
  EXPECT_EQ(m.endpoint, "tcp:127.0.0.1:1502");
  AgentSpec c = parse_agent_spec("5in=can:vcan0:0x310");
  EXPECT_TRUE(c.is_can);
  EXPECT_EQ(c.endpoint, "vcan0");
  EXPECT_EQ(c.can_base_id, 0x310u);
  EXPECT_EQ(parse_agent_spec("x=can:vcan1").can_base_id, 0x300u);
  EXPECT_THROW(parse_agent_spec("modbus:tcp:1.2.3.4:1"), ConfigError);
  EXPECT_THROW(parse_agent_spec("a=serial:/dev/tty"), ConfigError);
  EXPECT_THROW(parse_agent_spec("a b=can:vcan0"), ConfigError);
  EXPECT_THROW(parse_agent_spec("a=can:vcan0:0x7FF"), ConfigError);
}

TEST(AgentSpec, RecordingPathGetsTheLabelWhenSeveral) {
  EXPECT_EQ(recording_path_for("run/session.log", "4in", false), "run/session.log");
  EXPECT_EQ(recording_path_for("run/session.log", "4in", true), "run/session.4in.log");
  EXPECT_EQ(recording_path_for("run.d/session", "5in", true), "run.d/session.5in");
}

TEST(AgentSpec, NumberLists) {
  EXPECT_EQ(parse_number_list("20,50", "--lengths"), (std::vector<double>{20, 50}));
  EXPECT_THROW(parse_number_list("20,,50", "--lengths"), ConfigError);
  EXPECT_THROW(parse_number_list("abc", "--y"), ConfigError);
}

}  // namespace
}  // namespace cmmcomp::vc
