// SPDX-License-Identifier: MIT
/// @file Shared by the Modbus tests: the worked example of docs/protocol-modbus.md, a server on a
/// free loopback port in a thread, and a libmodbus client.
#pragma once

#include <modbus.h>
#include <unistd.h>

#include <array>
#include <atomic>
#include <cmmcomp/exceptions.hpp>
#include <cmmcomp/plugins/modbus_register_map.hpp>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstdint>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "modbus_example.hpp"
#include "support/compensation_models.hpp"

namespace cmmcomp::test {

// ---- worked example (docs/protocol-modbus.md, "Worked example"): model and request in
// modbus_example.hpp; its bytes here.

inline constexpr const char* kExampleWriteAdu =
    "00 01 00 00 00 39 01 10 00 00 00 19 32 00 00 00 00 3f 19 99 9a 00 00 00 00 bf 4c cc cd "
    "42 2a 00 00 43 48 00 00 41 a0 00 00 40 a0 00 00 42 48 00 00 40 00 00 00 43 7a 00 00 "
    "c2 c8 00 00 00 07";
inline constexpr const char* kExampleWriteResponseAdu = "00 01 00 00 00 06 01 10 00 00 00 19";
inline constexpr const char* kExampleReadAdu = "00 02 00 00 00 06 01 04 00 01 00 17";
inline constexpr const char* kExampleReadResponseAdu =
    "00 02 00 00 00 31 01 04 2e 00 07 00 00 00 01 00 00 00 00 41 30 00 00 bf c0 00 00 "
    "40 a0 00 00 40 00 00 00 3f 99 99 9a 00 00 00 00 bf cc cc cd 01 23 45 67 89 ab cd ef";

/// "00 1f …" → bytes.
inline std::vector<std::uint8_t> hex(const std::string& text) {
  std::vector<std::uint8_t> out;
  for (std::size_t i = 0; i + 1 < text.size(); ++i) {
    if (text[i] == ' ') continue;
    out.push_back(static_cast<std::uint8_t>(std::stoi(text.substr(i, 2), nullptr, 16)));
    ++i;
  }
  return out;
}

// ---- a server on loopback

/// A port for this process's attempt `attempt`: spread by pid so that parallel test processes
/// rarely meet, and retried on failure (libmodbus cannot bind port 0).
inline int candidate_port(int attempt) {
  return 20000 + static_cast<int>((static_cast<unsigned>(::getpid()) * 7919u +
                                   static_cast<unsigned>(attempt) * 104729u) %
                                  30000u);
}

/// A ModbusServer on 127.0.0.1 serving `compensator` from its own thread until destroyed.
class LoopbackServer {
 public:
  explicit LoopbackServer(const compensation::MoveCompensator& compensator,
                          plugins::ModbusServerOptions options = {}) {
    std::string last;
    for (int attempt = 0; attempt < 50 && !server_; ++attempt) {
      port_ = candidate_port(attempt);
      try {
        server_ = std::make_unique<plugins::ModbusServer>(
            compensator,
            plugins::ModbusEndpoint::parse("tcp:127.0.0.1:" + std::to_string(port_)),
            options);
      } catch (const Error& e) {
        last = e.what();
      }
    }
    if (!server_) throw Error("no free port: " + last);
    thread_ = std::thread([this] { server_->run(stop_); });
  }
  ~LoopbackServer() { stop(); }
  LoopbackServer(const LoopbackServer&) = delete;
  LoopbackServer& operator=(const LoopbackServer&) = delete;

  void stop() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
  }
  int port() const { return port_; }
  plugins::ModbusServer& server() { return *server_; }

 private:
  int port_ = 0;
  std::unique_ptr<plugins::ModbusServer> server_;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

/// A libmodbus TCP client (closed and freed on destruction).
struct ClientDeleter {
  void operator()(modbus_t* c) const {
    modbus_close(c);
    modbus_free(c);
  }
};
using Client = std::unique_ptr<modbus_t, ClientDeleter>;

inline Client connect_client(int port, int unit = 1) {
  Client c(modbus_new_tcp("127.0.0.1", port));
  if (!c) throw Error("modbus_new_tcp failed");
  modbus_set_slave(c.get(), unit);
  modbus_set_response_timeout(c.get(), 2, 0);
  if (modbus_connect(c.get()) != 0) {
    throw Error(std::string("connect: ") + modbus_strerror(errno));
  }
  return c;
}

/// Writes `m` (FC16, the whole request block, sequence last). libmodbus's return value.
inline int write_request(modbus_t* c, const compensation::MoveRequest& m) {
  plugins::modbus::HoldingRegisters h{};
  plugins::modbus::encode_request(m, h);
  return modbus_write_registers(c, 0, plugins::modbus::kRequestCount, h.data());
}

/// Reads every input register (FC04); false on error.
inline bool read_inputs(modbus_t* c, plugins::modbus::InputRegisters& in) {
  return modbus_read_input_registers(c, 0, plugins::modbus::kInputCount, in.data()) ==
         plugins::modbus::kInputCount;
}

/// One FC23 transaction: writes `m` and reads the result copy; false on error.
inline bool transact(modbus_t* c,
                     const compensation::MoveRequest& m,
                     plugins::modbus::Result& out) {
  namespace map = plugins::modbus;
  map::HoldingRegisters h{};
  map::encode_request(m, h);
  std::array<std::uint16_t, map::kResultWords> copy{};
  if (modbus_write_and_read_registers(
          c, 0, map::kRequestCount, h.data(), map::kResultCopy, map::kResultWords, copy.data()) !=
      map::kResultWords) {
    return false;
  }
  map::InputRegisters in{};
  for (std::size_t i = 0; i < copy.size(); ++i) in[map::kResultSequence + i] = copy[i];
  out = map::decode_result(in);
  return true;
}

}  // namespace cmmcomp::test
