// SPDX-License-Identifier: MIT
/// @file The register map without sockets: word order, encode/decode, field checks, the worked
/// example of docs/protocol-modbus.md and the document's register tables against the code.
#include <gtest/gtest.h>

#include <cmath>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstdint>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "modbus_example_result.hpp"
#include "modbus_test_support.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;
namespace map = cmmcomp::plugins::modbus;

TEST(ModbusRegisterMap, WordOrderIsMostSignificantFirst) {
  std::uint16_t r[4] = {};
  map::put_f32(r, 1.0f);
  EXPECT_EQ(r[0], 0x3F80);
  EXPECT_EQ(r[1], 0x0000);
  map::put_f32(r, -1.6f);
  EXPECT_EQ(r[0], 0xBFCC);
  EXPECT_EQ(r[1], 0xCCCD);
  EXPECT_EQ(map::get_f32(r), -1.6f);
  map::put_u32(r, 0x12345678u);
  EXPECT_EQ(r[0], 0x1234);
  EXPECT_EQ(r[1], 0x5678);
  EXPECT_EQ(map::get_u32(r), 0x12345678u);
  map::put_u64(r, 0x0123456789ABCDEFull);
  EXPECT_EQ(r[0], 0x0123);
  EXPECT_EQ(r[3], 0xCDEF);
  EXPECT_EQ(map::get_u64(r), 0x0123456789ABCDEFull);
}

TEST(ModbusRegisterMap, RequestRoundTripsThroughBinary32) {
  const compensation::MoveRequest m = test::example_request();
  map::HoldingRegisters h{};
  map::encode_request(m, h);
  compensation::MoveRequest back;
  ASSERT_EQ(map::decode_request(h, back), Status::kOk);
  EXPECT_EQ(back.sequence, 7u);
  EXPECT_EQ(back.axis, 0);
  EXPECT_EQ(back.direction[0], static_cast<double>(0.6f));
  EXPECT_EQ(back.direction[2], static_cast<double>(-0.8f));
  EXPECT_EQ(back.pv_mm_s, 42.5);
  EXPECT_EQ(back.pa_mm_s2, 200.0);
  EXPECT_EQ(back.pd_mm, 20.0);
  EXPECT_EQ(back.av_mm_s, 5.0);
  EXPECT_EQ(back.aa_mm_s2, 50.0);
  EXPECT_EQ(back.ad_mm, 2.0);
  EXPECT_EQ(back.y_mm, 250.0);
  EXPECT_EQ(back.z_mm, -100.0);
  // A unit vector rounded to binary32 still passes the compensator's |d| = 1 ± 1e-6 check.
  EXPECT_EQ(compensation::validate_move(back), Status::kOk);
}

TEST(ModbusRegisterMap, DecodeRefusesBadAxisAndReserved) {
  map::HoldingRegisters h{};
  map::encode_request(test::example_request(), h);
  compensation::MoveRequest m;
  h[map::kAxis] = 4;
  EXPECT_EQ(map::decode_request(h, m), Status::kInvalidInput);
  h[map::kAxis] = 3;
  h[map::kReserved] = 1;
  EXPECT_EQ(map::decode_request(h, m), Status::kInvalidInput);
}

TEST(ModbusRegisterMap, CheckFieldRefusesNanInfAndNonPositive) {
  map::HoldingRegisters h{};
  map::encode_request(test::example_request(), h);
  for (const auto& f : map::kHoldingFields) {
    if (f.address >= map::kRequestCount) continue;
    EXPECT_EQ(map::check_field(h, f.address), Status::kOk) << f.name;
  }
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(),
                       std::numeric_limits<float>::infinity()};
  for (std::uint16_t a = map::kDirectionX; a <= map::kZ; a = static_cast<std::uint16_t>(a + 2)) {
    for (float v : bad) {
      map::HoldingRegisters b = h;
      map::put_f32(&b[a], v);
      EXPECT_EQ(map::check_field(b, a), Status::kInvalidInput) << a;
      EXPECT_EQ(map::check_field(b, static_cast<std::uint16_t>(a + 1)), Status::kInvalidInput);
    }
  }
  for (std::uint16_t a = map::kPv; a <= map::kAd; a = static_cast<std::uint16_t>(a + 2)) {
    map::HoldingRegisters b = h;
    map::put_f32(&b[a], 0.0f);
    EXPECT_EQ(map::check_field(b, a), Status::kInvalidInput) << a;
    map::put_f32(&b[a], -3.0f);
    EXPECT_EQ(map::check_field(b, a), Status::kInvalidInput) << a;
  }
  map::HoldingRegisters b = h;
  map::put_f32(&b[map::kDirectionY], 1.5f);
  EXPECT_EQ(map::check_field(b, map::kDirectionY), Status::kInvalidInput);
  map::put_f32(&b[map::kY], -1e6f);  // positions may be negative
  EXPECT_EQ(map::check_field(b, map::kY), Status::kOk);
  b[map::kAxis] = 4;
  EXPECT_EQ(map::check_field(b, map::kAxis), Status::kInvalidInput);
  EXPECT_EQ(map::check_field(b, map::kResultCopy), Status::kInvalidInput);
}

TEST(ModbusRegisterMap, ResultNeverHoldsNanOrInf) {
  compensation::Correction c;
  c.mpe_um = 1e300;  // finite as double, not as binary32
  c.flags = compensation::kFlagOk;
  map::InputRegisters in{};
  map::encode_result(3, 1, Status::kOk, c, in);
  const map::Result r = map::decode_result(in);
  EXPECT_EQ(r.status, static_cast<std::int16_t>(Status::kInvalidInput));
  EXPECT_EQ(r.flags, compensation::kFlagInvalidInput);
  EXPECT_EQ(r.mpe_um, 0.0);
  EXPECT_EQ(r.sequence, 3);
  EXPECT_EQ(r.axis, 1);
}

TEST(ModbusRegisterMap, FailedStatusWritesZerosAndItsFlags) {
  compensation::Correction c;
  c.rae_um = 5.0;
  map::InputRegisters in{};
  map::encode_result(9, 2, Status::kNoModel, c, in);
  const map::Result r = map::decode_result(in);
  EXPECT_EQ(r.status, -101);
  EXPECT_EQ(r.flags, compensation::kFlagNoModel);
  EXPECT_EQ(r.rae_um, 0.0);
  EXPECT_EQ(r.model_id, 0u);
}

// Protocol version 2: the interval block carries U95 and every flag; the version-1 registers
// carry what they always did (result_flags without kFlagNoUncertainty).
TEST(ModbusRegisterMap, IntervalBlockCarriesU95AndEveryFlag) {
  compensation::Correction c;
  c.rae_um = -4.25;
  c.flags = compensation::kFlagOk | compensation::kFlagOutsideDomain;
  c.u95_um = {2.5, 1.75, 1.25, 0.5};
  map::InputRegisters in{};
  map::encode_result(5, 0, Status::kOutsideDomain, c, in);
  map::Result r = map::decode_result(in);
  EXPECT_EQ(r.flags, compensation::kFlagOk | compensation::kFlagOutsideDomain);
  EXPECT_EQ(r.interval_flags, compensation::kFlagOk | compensation::kFlagOutsideDomain);
  for (std::size_t k = 0; k < 4; ++k) EXPECT_EQ(r.u95_um[k], c.u95_um[k]) << k;
  EXPECT_EQ(in[map::kIntervalReserved], 0);

  c.flags = compensation::kFlagOk | compensation::kFlagNoUncertainty;
  c.u95_um = {0.0, 0.0, 0.0, 0.0};
  map::InputRegisters v1_view{};
  map::encode_result(6, 0, Status::kOk, c, v1_view);
  r = map::decode_result(v1_view);
  EXPECT_EQ(r.flags, compensation::kFlagOk);  // a version-1 client sees no new bit
  EXPECT_EQ(r.interval_flags, compensation::kFlagOk | compensation::kFlagNoUncertainty);

  // A failed status: zeros and the status's flags in both blocks.
  c.u95_um = {9.0, 9.0, 9.0, 9.0};
  map::encode_result(7, 0, Status::kNoModel, c, in);
  r = map::decode_result(in);
  EXPECT_EQ(r.interval_flags, compensation::kFlagNoModel);
  for (const double u : r.u95_um) EXPECT_EQ(u, 0.0);
  // A half-width beyond binary32 makes the whole result unusable, never inf on the wire.
  c.u95_um = {1e300, 0.0, 0.0, 0.0};
  c.flags = compensation::kFlagOk;
  map::encode_result(8, 0, Status::kOk, c, in);
  r = map::decode_result(in);
  EXPECT_EQ(r.status, static_cast<std::int16_t>(Status::kInvalidInput));
  EXPECT_EQ(r.u95_um[0], 0.0);
}

TEST(ModbusRegisterMap, FieldsTileTheMapWithoutGaps) {
  std::uint16_t next = 0;
  for (const auto& f : map::kHoldingFields) {
    EXPECT_EQ(f.address, next) << f.name;
    next = static_cast<std::uint16_t>(f.address + f.registers());
  }
  EXPECT_EQ(next, map::kHoldingCount);
  next = 0;
  for (const auto& f : map::kInputFields) {
    EXPECT_EQ(f.address, next) << f.name;
    next = static_cast<std::uint16_t>(f.address + f.registers());
  }
  EXPECT_EQ(next, map::kInputCount);
}

// ---- the worked example of docs/protocol-modbus.md

TEST(ModbusWorkedExample, RequestAndResponseBytes) {
  compensation::MoveCompensator comp;
  ASSERT_EQ(comp.publish(0, test::example_model(), test::kExampleModelId), Status::kOk);
  ModbusRequestHandler handler(comp, 1, ModbusTransport::kTcp);

  const std::vector<std::uint8_t> write = test::hex(test::kExampleWriteAdu);
  ASSERT_EQ(write.size(), 7u + 6u + 50u);
  // The bytes are what encode_request makes of the example request.
  map::HoldingRegisters h{};
  map::encode_request(test::example_request(), h);
  for (std::size_t i = 0; i < map::kRequestCount; ++i) {
    EXPECT_EQ(write[13 + 2 * i], h[i] >> 8) << i;
    EXPECT_EQ(write[14 + 2 * i], h[i] & 0xFF) << i;
  }
  const ModbusDecision w = handler.handle(write[6], write.data() + 7, write.size() - 7);
  ASSERT_EQ(w.kind, ModbusDecision::Kind::kReply);

  const std::vector<std::uint8_t> read = test::hex(test::kExampleReadAdu);
  ASSERT_EQ(handler.handle(read[6], read.data() + 7, read.size() - 7).kind,
            ModbusDecision::Kind::kReply);
  // The response's data bytes: input registers 1 .. 23 as the server holds them.
  const std::vector<std::uint8_t> response = test::hex(test::kExampleReadResponseAdu);
  ASSERT_EQ(response.size(), 9u + 46u);
  for (std::size_t i = 0; i < 23; ++i) {
    const std::uint16_t reg = handler.input()[1 + i];
    EXPECT_EQ(response[9 + 2 * i], reg >> 8) << i;
    EXPECT_EQ(response[10 + 2 * i], reg & 0xFF) << i;
  }
  test::expect_example_result(map::decode_result(handler.input()));
}

// ---- endpoints and options

TEST(ModbusEndpoint, ParsesTcp) {
  const ModbusEndpoint e = ModbusEndpoint::parse("tcp:127.0.0.1:1502");
  EXPECT_EQ(e.kind, ModbusEndpoint::Kind::kTcp);
  EXPECT_EQ(e.host, "127.0.0.1");
  EXPECT_EQ(e.port, 1502);
  EXPECT_EQ(e.to_string(), "tcp:127.0.0.1:1502");
  const ModbusEndpoint v6 = ModbusEndpoint::parse("tcp:[::1]:502");
  EXPECT_EQ(v6.host, "::1");
  EXPECT_EQ(v6.to_string(), "tcp:[::1]:502");
}

TEST(ModbusEndpoint, ParsesRtu) {
  const ModbusEndpoint e = ModbusEndpoint::parse("rtu:/dev/ttyUSB0:115200,8N1");
  EXPECT_EQ(e.kind, ModbusEndpoint::Kind::kRtu);
  EXPECT_EQ(e.device, "/dev/ttyUSB0");
  EXPECT_EQ(e.baud, 115200);
  EXPECT_EQ(e.data_bits, 8);
  EXPECT_EQ(e.parity, 'N');
  EXPECT_EQ(e.stop_bits, 1);
  EXPECT_EQ(ModbusEndpoint::parse(e.to_string()).to_string(), e.to_string());
  const ModbusEndpoint d = ModbusEndpoint::parse("rtu:/dev/ttyS1:9600");
  EXPECT_EQ(d.parity, 'E');  // the Modbus default framing 8E1
  EXPECT_EQ(ModbusEndpoint::parse("rtu:/dev/ttyS1:9600,7o2").parity, 'O');
}

/// The ConfigError message for `text` (empty when it parses).
std::string parse_error(const std::string& text) {
  try {
    ModbusEndpoint::parse(text);
  } catch (const ConfigError& e) {
    return e.what();
  }
  return {};
}

TEST(ModbusEndpoint, ErrorsNameWhatIsWrong) {
  EXPECT_NE(parse_error("udp:1.2.3.4:5").find("unknown transport"), std::string::npos);
  EXPECT_NE(parse_error("tcp:localhost").find("no port"), std::string::npos);
  EXPECT_NE(parse_error("tcp::1502").find("host is empty"), std::string::npos);
  EXPECT_NE(parse_error("tcp:localhost:99999").find("port must be 1..65535, not 99999"),
            std::string::npos);
  EXPECT_NE(parse_error("tcp:localhost:http").find("port 'http' is not a number"),
            std::string::npos);
  EXPECT_NE(parse_error("tcp:[::1:502").find("[ADDRESS]:PORT"), std::string::npos);
  EXPECT_NE(parse_error("rtu:/dev/ttyS0").find("no baud rate"), std::string::npos);
  EXPECT_NE(parse_error("rtu::9600").find("device is empty"), std::string::npos);
  EXPECT_NE(parse_error("rtu:/dev/ttyS0:fast").find("baud rate 'fast'"), std::string::npos);
  EXPECT_NE(parse_error("rtu:/dev/ttyS0:9600,8X1").find("parity 'X'"), std::string::npos);
  EXPECT_NE(parse_error("rtu:/dev/ttyS0:9600,9N1").find("framing '9N1'"), std::string::npos);
  EXPECT_NE(parse_error("tcp:localhost:0").find("'tcp:localhost:0'"), std::string::npos);
}

TEST(ModbusServerOptions, Validation) {
  std::string why;
  EXPECT_TRUE(ModbusServerOptions{}.is_valid(&why));
  ModbusServerOptions o;
  o.unit_id = 248;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_EQ(why, "unit_id must be 1..247");
  o = {};
  o.max_tcp_clients = 0;
  EXPECT_FALSE(o.is_valid(&why));
  o = {};
  o.frame_timeout_ms = o.byte_timeout_ms - 1;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_EQ(why, "frame_timeout_ms must be byte_timeout_ms..60000");
  o = {};
  o.idle_timeout_ms = -1;
  EXPECT_FALSE(o.is_valid(&why));
  o.idle_timeout_ms = 0;  // never
  EXPECT_TRUE(o.is_valid(&why));
  o.evict_idle_ms = -1;
  EXPECT_FALSE(o.is_valid(&why));
  EXPECT_EQ(why, "evict_idle_ms must be 0..86400000");
}

// ---- the document

std::string read_doc() {
  std::ifstream in(CMMCOMP_MODBUS_DOC);
  EXPECT_TRUE(in.good()) << "cannot read " << CMMCOMP_MODBUS_DOC;
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// One row of a register table in the document.
struct DocRow {
  int address = 0;
  int registers = 0;
  std::string unit;  ///< the unit cell, "" for "–"
};

/// name → row from the rows "| 2–3 | `direction_x` | f32 | – | …" of the section whose "## "
/// heading contains `section`.
std::map<std::string, DocRow> doc_table(const std::string& doc, const std::string& section) {
  std::map<std::string, DocRow> rows;
  std::istringstream lines(doc);
  std::string line;
  bool inside = false;
  while (std::getline(lines, line)) {
    if (line.rfind("## ", 0) == 0) inside = line.find(section) != std::string::npos;
    if (!inside || line.rfind("| ", 0) != 0) continue;
    const std::size_t bar = line.find('|', 2);
    const std::string cell = line.substr(2, bar - 2);
    if (cell.empty() || cell[0] < '0' || cell[0] > '9') continue;
    std::size_t used = 0;
    const int first = std::stoi(cell, &used);
    int last = first;
    const std::size_t dash = cell.find("–");  // en dash
    if (dash != std::string::npos) last = std::stoi(cell.substr(dash + std::string("–").size()));
    const std::size_t tick = line.find('`', bar);
    const std::size_t tock = line.find('`', tick + 1);
    if (tick == std::string::npos || tock == std::string::npos) continue;
    // The unit is the cell after the type: "| name | type | unit |".
    const std::size_t type_bar = line.find('|', line.find('|', tock) + 1);
    const std::size_t unit_bar = line.find('|', type_bar + 1);
    std::string unit = type_bar == std::string::npos || unit_bar == std::string::npos
                           ? "?"
                           : line.substr(type_bar + 1, unit_bar - type_bar - 1);
    unit.erase(0, unit.find_first_not_of(' '));
    unit.erase(unit.find_last_not_of(' ') + 1);
    if (unit == "–") unit.clear();
    rows[line.substr(tick + 1, tock - tick - 1)] = {first, last - first + 1, unit};
  }
  return rows;
}

template <std::size_t N>
void expect_same(const std::map<std::string, DocRow>& doc,
                 const std::array<map::Field, N>& code,
                 const char* what) {
  EXPECT_EQ(doc.size(), N) << what << ": the document lists " << doc.size() << " registers";
  for (const auto& f : code) {
    const auto it = doc.find(f.name);
    ASSERT_NE(it, doc.end()) << what << " register `" << f.name << "` is not in the document";
    EXPECT_EQ(it->second.address, f.address) << f.name;
    EXPECT_EQ(it->second.registers, f.registers()) << f.name;
    EXPECT_EQ(it->second.unit, f.unit) << f.name;
  }
}

TEST(ModbusProtocolDocument, HoldingTableMatchesTheCode) {
  expect_same(doc_table(read_doc(), "Holding registers"), map::kHoldingFields, "holding");
}

TEST(ModbusProtocolDocument, InputTableMatchesTheCode) {
  expect_same(doc_table(read_doc(), "Input registers"), map::kInputFields, "input");
}

TEST(ModbusProtocolDocument, WorkedExampleBytesAreTheTestedOnes) {
  const std::string doc = read_doc();
  EXPECT_NE(doc.find(test::kExampleWriteAdu), std::string::npos);
  EXPECT_NE(doc.find(test::kExampleWriteResponseAdu), std::string::npos);
  EXPECT_NE(doc.find(test::kExampleReadAdu), std::string::npos);
  EXPECT_NE(doc.find(test::kExampleReadResponseAdu), std::string::npos);
}

TEST(ModbusProtocolDocument, StatesTheProtocolVersion) {
  EXPECT_NE(read_doc().find("protocol version " + std::to_string(map::kProtocolVersion)),
            std::string::npos);
}

}  // namespace
