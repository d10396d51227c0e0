// SPDX-License-Identifier: MIT
/// @file cmmcomp-agent as a controller sees it, over Modbus TCP on loopback: the shipped default
/// model with its warning, answers equal to the in-process compensator's, SIGHUP hot reload,
/// a corrupt file on reload keeps the old model serving, SIGTERM exits cleanly, and bad
/// arguments are refused with a clear message.
#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <modbus/modbus.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <cerrno>
#include <chrono>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cmmcomp/io/model_file.hpp>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "support/loopback_socket.hpp"
#include "tools/agent/agent_process.hpp"

#ifndef CMMCOMP_AGENT_PATH
#error "CMMCOMP_AGENT_PATH must name the cmmcomp-agent executable"
#endif

namespace cmmcomp {
namespace {

namespace map = plugins::modbus;
using namespace std::chrono_literals;
using test::AgentProcess;

struct ClientDeleter {
  void operator()(modbus_t* c) const {
    modbus_close(c);
    modbus_free(c);
  }
};
using Client = std::unique_ptr<modbus_t, ClientDeleter>;

using test::RunningAgent;

RunningAgent start_agent(const std::vector<std::string>& extra) {
  std::string why;
  RunningAgent a = test::start_modbus_agent(CMMCOMP_AGENT_PATH, extra, 0, &why);
  if (!a.process) ADD_FAILURE() << why;
  return a;
}

Client connect(int port) {
  Client c(modbus_new_tcp("127.0.0.1", port));
  modbus_set_slave(c.get(), 1);
  modbus_set_response_timeout(c.get(), 2, 0);
  if (modbus_connect(c.get()) != 0) ADD_FAILURE() << "connect: " << modbus_strerror(errno);
  return c;
}

compensation::MoveRequest probing_move(std::uint32_t sequence) {
  compensation::MoveRequest m;
  m.sequence = sequence;
  m.axis = 0;
  m.direction = {-1.0, 0.0, 0.0};
  m.pv_mm_s = 70;
  m.pa_mm_s2 = 200;
  m.pd_mm = 55;
  m.av_mm_s = 12;
  m.aa_mm_s2 = 60;
  m.ad_mm = 9;
  m.y_mm = 250;
  return m;
}

/// Writes the request (FC16, sequence last: that write computes) and reads the result (FC04).
map::Result ask(modbus_t* c, const compensation::MoveRequest& m) {
  map::HoldingRegisters h{};
  map::encode_request(m, h);
  EXPECT_EQ(modbus_write_registers(c, 0, map::kRequestCount, h.data()), map::kRequestCount)
      << modbus_strerror(errno);
  map::InputRegisters in{};
  EXPECT_EQ(modbus_read_input_registers(c, 0, map::kInputCount, in.data()), map::kInputCount)
      << modbus_strerror(errno);
  return map::decode_result(in);
}

/// What the in-process compensator answers for `m` with `model` (the agent's floats: the
/// request crosses the wire as f32, the result too).
compensation::Correction expected(const io::ModelFileOf<PaperInputs>& file,
                                  compensation::MoveRequest m) {
  compensation::MoveCompensator comp;
  EXPECT_EQ(comp.publish(0, file.compensation_model(), 1), Status::kOk);
  for (double* v :
       {&m.pv_mm_s, &m.pa_mm_s2, &m.pd_mm, &m.av_mm_s, &m.aa_mm_s2, &m.ad_mm, &m.y_mm, &m.z_mm}) {
    *v = static_cast<double>(static_cast<float>(*v));
  }
  compensation::Correction out;
  EXPECT_TRUE(ok(comp.before_approach(m, out)));
  return out;
}

void expect_same(const map::Result& got, const compensation::Correction& want) {
  EXPECT_EQ(got.status, 0);
  EXPECT_FLOAT_EQ(static_cast<float>(got.mpe_um), static_cast<float>(want.mpe_um));
  EXPECT_FLOAT_EQ(static_cast<float>(got.rpe_um), static_cast<float>(want.rpe_um));
  EXPECT_FLOAT_EQ(static_cast<float>(got.mae_um), static_cast<float>(want.mae_um));
  EXPECT_FLOAT_EQ(static_cast<float>(got.rae_um), static_cast<float>(want.rae_um));
  EXPECT_FLOAT_EQ(static_cast<float>(got.correction_um[0]),
                  static_cast<float>(want.correction_um[0]));
}

std::uint64_t id_of(const io::ModelFile<4, 3, 4>& f) {
  return std::strtoull(f.model_id.c_str(), nullptr, 16);
}

std::filesystem::path scratch(const std::string& name) {
  const auto dir =
      std::filesystem::temp_directory_path() / ("cmmcomp-agent-test-" + std::to_string(getpid()));
  std::filesystem::create_directories(dir);
  return dir / name;
}

TEST(Agent, ServesTheShippedDefaultModelAndSaysItIsSimulated) {
  RunningAgent agent = start_agent({});
  ASSERT_TRUE(agent.process);
  EXPECT_NE(agent.process->output().find("simulated default machine"), std::string::npos)
      << agent.process->output();
  const auto model = io::default_model_file();
  Client c = connect(agent.port);
  const map::Result r = ask(c.get(), probing_move(41));
  EXPECT_EQ(r.sequence, 41);
  EXPECT_EQ(r.model_id, id_of(model));
  expect_same(r, expected(model, probing_move(41)));
  agent.process->signal(SIGTERM);
  EXPECT_EQ(agent.process->wait_exit(5s), 0) << agent.process->output();
  EXPECT_NE(agent.process->output().find("1 computations"), std::string::npos)
      << agent.process->output();
}

// Issue 36: the shipped model (trained at PA 200) answered a move at PA 1200 as plain OK, and
// nothing was logged. Now: refused, flagged, logged with the move, and counted.
TEST(Agent, RefusesAndLogsMovesOutsideTheModelsConditions) {
  RunningAgent agent = start_agent({});
  ASSERT_TRUE(agent.process);
  Client c = connect(agent.port);
  compensation::MoveRequest far = probing_move(51);
  far.pa_mm_s2 = 1200;
  EXPECT_EQ(ask(c.get(), far).status, static_cast<std::int16_t>(Status::kOutsideDomainRejected));
  compensation::MoveRequest near = probing_move(52);
  near.pa_mm_s2 = 210;
  const map::Result flagged = ask(c.get(), near);
  EXPECT_EQ(flagged.status, static_cast<std::int16_t>(Status::kOutsideDomain));
  EXPECT_NE(flagged.flags & compensation::kFlagOutsideDomain, 0u);
  EXPECT_TRUE(agent.process->wait_for_output("sequence 52 axis 0", 5s)) << agent.process->output();
  const std::string& text = agent.process->output();
  EXPECT_NE(text.find("sequence 51 axis 0: PV 70 mm/s, PD 55 mm, AV 12 mm/s, AD 9 mm, PA 1200 "
                      "mm/s²"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("refused: outside the model's domain"), std::string::npos) << text;
  EXPECT_NE(text.find("answered OUTSIDE the model's domain"), std::string::npos) << text;
  agent.process->signal(SIGTERM);
  EXPECT_EQ(agent.process->wait_exit(5s), 0) << agent.process->output();
  EXPECT_NE(agent.process->output().find(
                "2 computations (1 refused by the compensator, 1 outside the model's domain)"),
            std::string::npos)
      << agent.process->output();
}

TEST(Agent, SighupReloadsAndABadFileKeepsTheOldModelServing) {
  auto a = io::default_model_file();
  auto b = a;
  for (int j = 0; j < 81; ++j) b.model.params.consequent(3, j, 0) += 1.5;  // RAE + 1.5 µm
  const auto path = scratch("model.json").string();
  io::save_model_file(path, a);
  a = io::load_model_file_of<PaperInputs>(path);

  RunningAgent agent = start_agent({"--model", "0=" + path});
  ASSERT_TRUE(agent.process);
  Client c = connect(agent.port);
  map::Result r = ask(c.get(), probing_move(1));
  EXPECT_EQ(r.model_id, id_of(a));
  expect_same(r, expected(a, probing_move(1)));

  io::save_model_file(path, b);
  b = io::load_model_file_of<PaperInputs>(path);
  agent.process->signal(SIGHUP);
  ASSERT_TRUE(agent.process->wait_for_output("reloaded model " + b.model_id, 5s))
      << agent.process->output();
  r = ask(c.get(), probing_move(2));
  EXPECT_EQ(r.model_id, id_of(b));
  expect_same(r, expected(b, probing_move(2)));
  EXPECT_NEAR(r.rae_um, expected(a, probing_move(2)).rae_um + 1.5, 1e-4);

  { std::ofstream(path, std::ios::trunc) << "{\"format\": \"cmmcomp-tsk-model\", \"format_ver"; }
  agent.process->signal(SIGHUP);
  ASSERT_TRUE(agent.process->wait_for_output("keeps serving", 5s)) << agent.process->output();
  EXPECT_NE(agent.process->output().find("model " + b.model_id + " keeps serving"),
            std::string::npos);
  r = ask(c.get(), probing_move(3));
  EXPECT_EQ(r.model_id, id_of(b));
  expect_same(r, expected(b, probing_move(3)));

  // A FIFO at the model path used to block the reload, and with it SIGTERM (issue 16 D6).
  std::filesystem::remove(path);
  ASSERT_EQ(::mkfifo(path.c_str(), 0600), 0);
  agent.process->signal(SIGHUP);
  ASSERT_TRUE(agent.process->wait_for_output("not a regular file", 5s)) << agent.process->output();
  r = ask(c.get(), probing_move(4));
  EXPECT_EQ(r.model_id, id_of(b));

  agent.process->signal(SIGTERM);
  EXPECT_EQ(agent.process->wait_exit(5s), 0) << agent.process->output();
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
}

/// An agent started with `--config FILE` serving Modbus TCP on a free loopback port: the config
/// `body` (sections and keys, without [modbus]) is written with the port, retried when taken.
struct ConfiguredAgent {
  RunningAgent agent;
  std::string config;
};
std::string modbus_section(int port) {
  return "[modbus]\nendpoint = \"tcp:127.0.0.1:" + std::to_string(port) + "\"\n";
}
ConfiguredAgent start_configured_agent(const std::string& config, const std::string& body) {
  for (int attempt = 0; attempt < 20; ++attempt) {
    const int port = 20000 + static_cast<int>((getpid() * 61 + attempt * 139 + 7) % 25000);
    { std::ofstream(config, std::ios::trunc) << body << modbus_section(port); }
    auto p = std::make_unique<AgentProcess>(CMMCOMP_AGENT_PATH,
                                            std::vector<std::string>{"--config", config});
    if (p->wait_for_output("listening on Modbus TCP", 10s)) return {{std::move(p), port}, config};
    if (p->output().find("in use") == std::string::npos) {
      ADD_FAILURE() << "agent did not start:\n" << p->output();
      return {};
    }
  }
  ADD_FAILURE() << "no free port";
  return {};
}

// docs/agent.md: the config file sets the models (relative to its folder); SIGHUP re-reads it;
// a bad config changes nothing (not even the models); a bus change waits for a restart.
TEST(Agent, ConfigFileServesAndSighupRereadsItKeepingEverythingOnABadOne) {
  auto a = io::default_model_file();
  auto b = a;
  for (int j = 0; j < 81; ++j) b.model.params.consequent(3, j, 0) += 1.5;  // RAE + 1.5 µm
  const auto dir = scratch("config-test").parent_path() / "config";
  std::filesystem::create_directories(dir);
  io::save_model_file((dir / "a.json").string(), a);
  io::save_model_file((dir / "b.json").string(), b);
  a = io::load_model_file_of<PaperInputs>((dir / "a.json").string());
  b = io::load_model_file_of<PaperInputs>((dir / "b.json").string());
  const std::string config = (dir / "agent.toml").string();
  const std::string head = "format_version = 1\nlog_level = \"info\"\n";

  ConfiguredAgent ca = start_configured_agent(config, head + "[models]\n0 = \"a.json\"\n");
  ASSERT_TRUE(ca.agent.process);
  AgentProcess& agent = *ca.agent.process;
  Client c = connect(ca.agent.port);
  map::Result r = ask(c.get(), probing_move(1));
  EXPECT_EQ(r.model_id, id_of(a));
  expect_same(r, expected(a, probing_move(1)));

  // A broken config: nothing changes, although it names model b.
  {
    std::ofstream(config, std::ios::trunc) << head << "[models]\n0 = \"b.json\"\n"
                                           << modbus_section(ca.agent.port) << "unit = 0\n";
  }
  agent.signal(SIGHUP);
  ASSERT_TRUE(agent.wait_for_output("keeps serving as it was", 5s)) << agent.output();
  EXPECT_NE(agent.output().find("agent.toml:7: 'modbus.unit' = 0 is outside 1 .. 247"),
            std::string::npos)
      << agent.output();
  r = ask(c.get(), probing_move(2));
  EXPECT_EQ(r.model_id, id_of(a));

  // A good config with model b and another unit: b serves, the unit waits for a restart.
  {
    std::ofstream(config, std::ios::trunc) << head << "[models]\n0 = \"b.json\"\n"
                                           << modbus_section(ca.agent.port) << "unit = 2\n";
  }
  agent.signal(SIGHUP);
  ASSERT_TRUE(agent.wait_for_output("reloaded model " + b.model_id, 5s)) << agent.output();
  EXPECT_NE(agent.output().find("[modbus] changed in"), std::string::npos) << agent.output();
  r = ask(c.get(), probing_move(3));  // still unit 1
  EXPECT_EQ(r.model_id, id_of(b));
  expect_same(r, expected(b, probing_move(3)));

  agent.signal(SIGTERM);
  EXPECT_EQ(agent.wait_exit(5s), 0) << agent.output();
  std::filesystem::remove_all(dir.parent_path());
}

/// The agent's resident set [kB], from /proc.
long rss_kb(pid_t pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("VmRSS:", 0) == 0) return std::strtol(line.c_str() + 6, nullptr, 10);
  }
  return -1;
}

/// Sends `adu` on a fresh connection; returns the answer's bytes, empty when the agent dropped
/// the connection without one (`*closed`) or sent nothing within the 5 s receive timeout. A
/// connection dropped with bytes still unread in the agent's socket arrives as a reset, not an
/// end of stream: both count as closed.
std::vector<std::uint8_t> exchange(int port, const std::vector<std::uint8_t>& adu, bool* closed) {
  const int fd = test::raw_connect(port, 5);
  std::vector<std::uint8_t> answer(300);
  *closed = false;
  if (fd < 0 ||
      ::send(fd, adu.data(), adu.size(), MSG_NOSIGNAL) != static_cast<ssize_t>(adu.size())) {
    ADD_FAILURE() << "cannot send to the agent";
    if (fd >= 0) ::close(fd);
    return {};
  }
  const ssize_t n = ::recv(fd, answer.data(), answer.size(), 0);
  *closed = n == 0 || (n < 0 && errno == ECONNRESET);
  answer.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
  ::close(fd);
  return answer;
}

// Issue 16, bad input at the process level: malformed and hostile Modbus TCP traffic, bounded in
// count and time; afterwards a well-formed client is served and the agent's memory is flat.
TEST(Agent, HostileModbusTrafficLeavesTheAgentServing) {
  RunningAgent agent = start_agent({});
  ASSERT_TRUE(agent.process);
  {
    Client warm = connect(agent.port);
    EXPECT_EQ(ask(warm.get(), probing_move(1)).sequence, 1);
  }
  const long rss_before = rss_kb(agent.process->pid());
  ASSERT_GT(rss_before, 0);
  for (int round = 0; round < 20; ++round) {
    bool closed = false;
    // Truncated MBAP header, then gone.
    const int t = test::raw_connect(agent.port);
    ASSERT_GE(t, 0);
    ASSERT_EQ(::send(t, "\0\1\0", 3, MSG_NOSIGNAL), 3);
    ::close(t);
    // Wrong protocol id, a length over 260, a length that disagrees with FC06: closed, no answer.
    for (const std::vector<std::uint8_t>& bad :
         {std::vector<std::uint8_t>{0, 1, 0, 7, 0, 6, 1, 0x06, 0, 0, 0, 1},
          std::vector<std::uint8_t>{0, 1, 0, 0, 1, 0x2C, 1, 0x03},
          std::vector<std::uint8_t>{0, 1, 0, 0, 0, 9, 1, 0x06, 0, 0, 0, 1, 0, 0, 0}}) {
      EXPECT_TRUE(exchange(agent.port, bad, &closed).empty());
      EXPECT_TRUE(closed);
    }
    // An unknown function code: exception 01. A NaN write: exception 03.
    std::vector<std::uint8_t> a = exchange(agent.port, {0, 2, 0, 0, 0, 2, 1, 0x41}, &closed);
    ASSERT_EQ(a.size(), 9u);
    EXPECT_EQ(a[7], 0xC1);
    EXPECT_EQ(a[8], 0x01);
    a = exchange(agent.port, {0, 3, 0, 0, 0, 6, 1, 0x06, 0, map::kPv, 0x7F, 0xC0}, &closed);
    ASSERT_EQ(a.size(), 9u);
    EXPECT_EQ(a[7], 0x86);
    EXPECT_EQ(a[8], 0x03);
  }
  // 200 connections at once, all idle, then gone.
  std::vector<int> flood;
  for (int i = 0; i < 200; ++i) {
    const int fd = test::raw_connect(agent.port);
    if (fd >= 0) flood.push_back(fd);
  }
  EXPECT_EQ(flood.size(), 200u);
  for (const int fd : flood) ::close(fd);
  // A well-formed client is served; the agent grew by less than 4 MiB over all of it.
  Client good;
  for (int attempt = 0; attempt < 50; ++attempt) {  // until the closes are noticed
    good = connect(agent.port);
    std::uint16_t reg = 0;
    if (modbus_read_input_registers(good.get(), 0, 1, &reg) == 1) break;
    std::this_thread::sleep_for(100ms);
  }
  const map::Result r = ask(good.get(), probing_move(77));
  EXPECT_EQ(r.sequence, 77);
  EXPECT_EQ(r.status, 0);
  const long rss_after = rss_kb(agent.process->pid());
  EXPECT_LT(rss_after - rss_before, 4096) << rss_before << " kB -> " << rss_after << " kB";
  agent.process->signal(SIGTERM);
  EXPECT_EQ(agent.process->wait_exit(5s), 0) << agent.process->output();
}

TEST(Agent, RefusesBadArgumentsWithAClearMessage) {
  struct Case {
    std::vector<std::string> args;
    std::string message;
  };
  const std::vector<Case> cases{
      {{}, "nothing to serve"},
      {{"--modbus", "tcp:127.0.0.1:99999"}, "port"},
      {{"--modbus", "tcp:127.0.0.1:1502", "--model", "/nonexistent/model.json"},
       "/nonexistent/model.json: cannot open model file"},
      {{"--modbus", "tcp:127.0.0.1:1502", "--model", "7=/x.json"}, "axis '7'"},
      {{"--can", "vcan0", "--can-base-id", "0x900"}, "11-bit"},
      {{"--config", "/nonexistent/agent.toml"},
       "/nonexistent/agent.toml: cannot open agent config"},
      {{"--config", "/etc/cmmcomp/agent.toml", "--modbus", "tcp:127.0.0.1:1502"},
       "--modbus and --config"},
  };
  for (const Case& k : cases) {
    AgentProcess p(CMMCOMP_AGENT_PATH, k.args);
    EXPECT_EQ(p.wait_exit(10s), 2) << p.output();
    EXPECT_NE(p.output().find(k.message), std::string::npos)
        << "expected '" << k.message << "' in:\n"
        << p.output();
  }
}

}  // namespace
}  // namespace cmmcomp
