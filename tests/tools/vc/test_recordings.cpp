// SPDX-License-Identifier: MIT
/// @file The recording formats exactly as docs/recordings.md shows them, the MBAP splitter, the
/// recording relay against a loopback echo peer, and the command-line agent specifications.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/vc/correction_source.hpp>
#include <cmmcomp/vc/per_y_source.hpp>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "agent_spec.hpp"
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

TEST(AgentSpec, ParsesAModelPerY) {
  const AgentSpec a = parse_agent_spec("per-y@250=modbus:tcp:127.0.0.1:1502");
  EXPECT_EQ(a.label, "per-y");
  EXPECT_TRUE(a.has_y);
  EXPECT_EQ(a.y_mm, 250);
  EXPECT_EQ(a.endpoint, "tcp:127.0.0.1:1502");
  EXPECT_EQ(parse_agent_spec("x@-12.5=can:vcan0").y_mm, -12.5);
  EXPECT_FALSE(parse_agent_spec("x=can:vcan0").has_y);
  EXPECT_THROW(parse_agent_spec("x@=can:vcan0"), ConfigError);
  EXPECT_THROW(parse_agent_spec("x@25mm=can:vcan0"), ConfigError);
  EXPECT_THROW(parse_agent_spec("x@nan=can:vcan0"), ConfigError);
  EXPECT_THROW(parse_agent_spec("@250=can:vcan0"), ConfigError);
}

/// An agent that answers with its own id, and counts what it was asked.
class FixedSource final : public CorrectionSource {
 public:
  FixedSource(std::string where, std::uint64_t id) : where_(std::move(where)), id_(id) {}
  Answer ask(const cmmcomp::compensation::MoveRequest& move) override {
    asked_y_.push_back(move.y_mm);
    Answer a;
    a.usable = true;
    a.model_id = id_;
    return a;
  }
  const std::string& label() const noexcept override { return label_; }
  const std::string& where() const noexcept override { return where_; }
  std::vector<double> asked_y_;

 private:
  std::string label_ = "fixed";
  std::string where_;
  std::uint64_t id_;
};

TEST(PerYSource, AsksTheAgentOfEachMovesY) {
  auto at0 = std::make_unique<FixedSource>("modbus a", 10);
  auto at500 = std::make_unique<FixedSource>("modbus b", 50);
  FixedSource* first = at0.get();
  FixedSource* second = at500.get();
  std::vector<std::pair<double, std::unique_ptr<CorrectionSource>>> agents;
  agents.emplace_back(0.0, std::move(at0));
  agents.emplace_back(500.0, std::move(at500));
  cmmcomp::vc::PerYSource source("per-y", std::move(agents));
  EXPECT_EQ(source.label(), "per-y");
  EXPECT_EQ(source.where(), "Y 0: modbus a; Y 500: modbus b");
  cmmcomp::compensation::MoveRequest m;
  m.y_mm = 500;
  EXPECT_EQ(source.ask(m).model_id, 50u);
  m.y_mm = 0;
  EXPECT_EQ(source.ask(m).model_id, 10u);
  EXPECT_EQ(first->asked_y_, std::vector<double>{0.0});
  EXPECT_EQ(second->asked_y_, std::vector<double>{500.0});
  EXPECT_TRUE(source.serves(500.0000001));
  EXPECT_FALSE(source.serves(250));
  m.y_mm = 250;
  const Answer refused = source.ask(m);
  EXPECT_FALSE(refused.usable);
  EXPECT_NE(refused.note.find("no agent of 'per-y' for Y 250 mm"), std::string::npos);
  EXPECT_EQ(first->asked_y_.size() + second->asked_y_.size(), 2u);
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
