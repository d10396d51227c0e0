// SPDX-License-Identifier: MIT
/// @file CAN request → response latency on a real vcan bus: a CanServer in one thread, a raw socket
/// as the controller in another; N round trips (three frames each way), then p50, p99, max.
/// The kernel must have CAN: run it inside User-Mode Linux, where every syscall is slow, so
/// the figures are UML figures, not hardware figures:
///   bash scripts/uml-run.sh -- build/release/plugins/can/bench/can_latency [N] [interface]
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmmcomp/plugins/can_server.hpp>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <thread>
#include <vector>

#include "can_peer.hpp"
#include "can_test_frames.hpp"

int main(int argc, char** argv) {
  using namespace cmmcomp;
  using namespace cmmcomp::plugins::can;
  const int n = argc > 1 ? std::atoi(argv[1]) : 2000;
  const std::string interface = argc > 2 ? argv[2] : "vcan0";
  if (n <= 0) {
    std::fprintf(stderr, "usage: can_latency [N > 0] [interface]\n");
    return 2;
  }
  try {
    compensation::MoveCompensator comp;
    (void)comp.publish(0, cmmcomp::test::example_model(), cmmcomp::test::kExampleModelId);
    plugins::CanServerOptions options;
    options.interface = interface;
    options.heartbeat_period = std::chrono::milliseconds(0);
    plugins::CanServer server(comp, options);
    std::atomic<bool> stop{false};
    std::thread thread([&] { server.run(stop); });
    cmmcomp::test::CanPeer peer(interface, options.base_id);

    std::vector<double> us;
    us.reserve(static_cast<std::size_t>(n));
    int failures = 0;
    for (int i = 0; i < n; ++i) {
      compensation::MoveRequest m = cmmcomp::test::example_move();
      m.sequence = static_cast<std::uint32_t>(i % 64);
      m.pv_mm_s = 5.0 + (i % 76);
      RequestFrames request;
      (void)encode_request(m, options.base_id, request);
      const auto t0 = std::chrono::steady_clock::now();
      bool ok = peer.send(request[0]) && peer.send(request[1]) && peer.send(request[2]);
      ResponseFrames response;
      for (Frame& f : response) ok = ok && peer.receive(f, 1000);
      const auto t1 = std::chrono::steady_clock::now();
      DecodedResponse d;
      if (!ok || !decode_response(response, options.base_id, d) ||
          d.correction.sequence != m.sequence) {
        ++failures;
        continue;
      }
      us.push_back(std::chrono::duration<double, std::micro>(t1 - t0).count());
    }
    stop.store(true);
    thread.join();
    if (us.empty()) {
      std::fprintf(stderr, "can_latency: no round trip succeeded\n");
      return 1;
    }
    std::sort(us.begin(), us.end());
    const auto at = [&us](double q) {
      return us[std::min(us.size() - 1,
                         static_cast<std::size_t>(q * static_cast<double>(us.size())))];
    };
    std::printf(
        "can_latency on %s (%s): %zu round trips (request 3 frames, response 3 frames), "
        "%d failed\n",
        interface.c_str(),
        "UML figure, not hardware",
        us.size(),
        failures);
    std::printf("p50 %.1f us, p90 %.1f us, p99 %.1f us, max %.1f us\n",
                at(0.50),
                at(0.90),
                at(0.99),
                us.back());
    return failures == 0 ? 0 : 1;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "can_latency: %s\n", e.what());
    return 1;
  }
}
