// SPDX-License-Identifier: MIT
/// @file cmmcomp-agent as a controller sees it, over Modbus TCP on loopback: the shipped default
/// model with its warning, answers equal to the in-process compensator's, SIGHUP hot reload,
/// a corrupt file on reload keeps the old model serving, SIGTERM exits cleanly, and bad
/// arguments are refused with a clear message.
#include <gtest/gtest.h>
#include <modbus/modbus.h>
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

#include "agent/agent_process.hpp"

#ifndef CMMCOMP_AGENT_PATH
#error "CMMCOMP_AGENT_PATH must name the cmmcomp-agent executable"
#endif

namespace cmmcomp {
namespace {

namespace map = plugins::modbus_map;
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
compensation::Correction expected(const io::ModelFile<4, 3, 4>& file, compensation::MoveRequest m) {
  compensation::MoveCompensator comp;
  EXPECT_EQ(comp.publish(0, file.model, 1), Status::kOk);
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

TEST(Agent, SighupReloadsAndABadFileKeepsTheOldModelServing) {
  auto a = io::default_model_file();
  auto b = a;
  for (int j = 0; j < 81; ++j) b.model.params.consequent(3, j, 0) += 1.5;  // RAE + 1.5 µm
  const auto path = scratch("model.json").string();
  io::save_model_file(path, a);
  a = io::load_model_file<4, 3, 4>(path);

  RunningAgent agent = start_agent({"--model", "0=" + path});
  ASSERT_TRUE(agent.process);
  Client c = connect(agent.port);
  map::Result r = ask(c.get(), probing_move(1));
  EXPECT_EQ(r.model_id, id_of(a));
  expect_same(r, expected(a, probing_move(1)));

  io::save_model_file(path, b);
  b = io::load_model_file<4, 3, 4>(path);
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

  agent.process->signal(SIGTERM);
  EXPECT_EQ(agent.process->wait_exit(5s), 0) << agent.process->output();
  std::filesystem::remove_all(std::filesystem::path(path).parent_path());
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
