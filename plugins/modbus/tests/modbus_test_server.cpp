// SPDX-License-Identifier: MIT
/// @file A Modbus TCP server on 127.0.0.1 serving the worked example's closed-form model on
/// axis 0 (for outside clients such as mbpoll). Usage: modbus_test_server [PORT]; without PORT
/// it tries ports derived from its pid until one is free. Prints "listening on PORT" once ready;
/// SIGTERM or SIGINT stops it (exit 0).
#include <signal.h>

#include <atomic>
#include <cmmcomp/plugins/modbus_server.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <memory>
#include <string>

#include "modbus_test_support.hpp"

namespace {

std::atomic<bool> g_stop{false};

extern "C" void on_signal(int) { g_stop = true; }

}  // namespace

int main(int argc, char** argv) {
  using namespace cmmcomp;
  try {
    struct sigaction sa {};
    sa.sa_handler = on_signal;
    sigaction(SIGTERM, &sa, nullptr);
    sigaction(SIGINT, &sa, nullptr);

    compensation::MoveCompensator comp;
    if (comp.publish(0, test::example_model(), test::kExampleModelId) != Status::kOk) {
      std::fprintf(stderr, "modbus_test_server: the example model does not validate\n");
      return 1;
    }
    std::unique_ptr<plugins::ModbusServer> server;
    std::string last;
    const int fixed = argc > 1 ? std::atoi(argv[1]) : 0;
    for (int attempt = 0; attempt < (fixed > 0 ? 1 : 50) && !server; ++attempt) {
      const int port = fixed > 0 ? fixed : test::candidate_port(attempt);
      try {
        server = std::make_unique<plugins::ModbusServer>(
            comp, plugins::ModbusEndpoint::parse("tcp:127.0.0.1:" + std::to_string(port)));
        std::printf("listening on %d (%s)\n", port, server->where().c_str());
      } catch (const Error& e) {
        last = e.what();
      }
    }
    if (!server) {
      std::fprintf(stderr, "modbus_test_server: %s\n", last.c_str());
      return 1;
    }
    std::fflush(stdout);
    server->run(g_stop);
    const plugins::ModbusCounters n = server->counters();
    std::printf("stopped: %llu requests, %llu exceptions\n",
                static_cast<unsigned long long>(n.requests),
                static_cast<unsigned long long>(n.exceptions));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "modbus_test_server: %s\n", e.what());
    return 1;
  }
}
