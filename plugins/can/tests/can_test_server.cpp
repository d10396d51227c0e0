// SPDX-License-Identifier: MIT
/// @file A CanServer for the HIL tests: serves the protocol document's closed-form example model on
/// axis 0 (model id 0xC0FFEE01, with the second example's interval calibration), prints "ready:
/// <where>" once it listens and its counters when SIGTERM, SIGINT or --max-seconds stop it.
///   can_test_server [--interface vcan0] [--base-id 0x300] [--part-timeout-ms 50]
///                   [--heartbeat-ms 1000] [--max-seconds 60] [--fd 0|1]
#include <unistd.h>

#include <atomic>
#include <cmmcomp/plugins/can_server.hpp>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <string>

#include "can_test_frames.hpp"

namespace {

std::atomic<bool> g_stop{false};
static_assert(std::atomic<bool>::is_always_lock_free, "set from a signal handler");

extern "C" void on_signal(int) { g_stop.store(true); }

}  // namespace

int main(int argc, char** argv) {
  using cmmcomp::plugins::CanServerOptions;
  CanServerOptions options;
  unsigned max_seconds = 60;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const char* value = argv[i + 1];
    if (flag == "--interface") {
      options.interface = value;
    } else if (flag == "--base-id") {
      options.base_id = static_cast<std::uint32_t>(std::strtoul(value, nullptr, 0));
    } else if (flag == "--part-timeout-ms") {
      options.part_timeout = std::chrono::milliseconds(std::atoi(value));
    } else if (flag == "--heartbeat-ms") {
      options.heartbeat_period = std::chrono::milliseconds(std::atoi(value));
    } else if (flag == "--fd") {
      options.fd = std::atoi(value) != 0;
    } else if (flag == "--max-seconds") {
      max_seconds = static_cast<unsigned>(std::atoi(value));
    } else {
      std::fprintf(stderr, "can_test_server: unknown flag %s\n", flag.c_str());
      return 2;
    }
  }
  try {
    cmmcomp::compensation::MoveCompensator comp;
    if (cmmcomp::test::publish_example(comp) != cmmcomp::Status::kOk) {
      std::fprintf(stderr, "can_test_server: example model refused\n");
      return 1;
    }
    cmmcomp::plugins::CanServer server(comp, options);
    std::signal(SIGTERM, on_signal);
    std::signal(SIGINT, on_signal);
    std::signal(SIGALRM, on_signal);
    alarm(max_seconds);
    std::printf("ready: %s\n", server.where().c_str());
    std::fflush(stdout);
    server.run(g_stop);
    const cmmcomp::plugins::CanCounters c = server.counters();
    std::printf(
        "counters: frames_in=%llu requests=%llu answered=%llu intervals=%llu rejected=%llu "
        "malformed=%llu timeouts=%llu out_of_range=%llu heartbeats=%llu send_errors=%llu "
        "ignored=%llu\n",
        static_cast<unsigned long long>(c.frames_in),
        static_cast<unsigned long long>(c.requests),
        static_cast<unsigned long long>(c.answered),
        static_cast<unsigned long long>(c.intervals),
        static_cast<unsigned long long>(c.rejected),
        static_cast<unsigned long long>(c.malformed),
        static_cast<unsigned long long>(c.timeouts),
        static_cast<unsigned long long>(c.out_of_range),
        static_cast<unsigned long long>(c.heartbeats),
        static_cast<unsigned long long>(c.send_errors),
        static_cast<unsigned long long>(c.ignored));
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "can_test_server: %s\n", e.what());
    return 1;
  }
}
