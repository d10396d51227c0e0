// SPDX-License-Identifier: MIT
/// @file The compensating I++ DME proxy's added latency per line (docs/protocol-ippdme.md,
/// "Performance"): a client on loopback sends one command every millisecond (1000 lines/s) to
/// the twin's I++ server, directly and through the proxy (the shipped model), and times each
/// command from its send to its `%`. The program repeats GoTo, GoTo, PtMeas: every third line's
/// answer is a corrected data line. Counters: p50 and p99 of each path [µs] and their
/// differences, the proxy's added latency.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmmcomp/dynamics/machine.hpp>
#include <cmmcomp/ipp/client.hpp>
#include <cmmcomp/ipp/server.hpp>
#include <cmmcomp/ipp/session.hpp>
#include <cmmcomp/vc/ipp_twin_machine.hpp>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "ipp_proxy.hpp"
#include "model_slots.hpp"

namespace {

namespace ipp = cmmcomp::ipp;
using Clock = std::chrono::steady_clock;

constexpr int kLines = 3000;

/// Send-to-`%` times [µs] of kLines commands paced at 1 ms.
std::vector<double> timed_session(std::uint16_t port) {
  ipp::Client c("127.0.0.1", port);
  c.call("StartSession()");
  c.call("SetProp(Tool.GoToPar.Speed(40), Tool.GoToPar.Accel(200))");
  c.call(
      "SetProp(Tool.PtMeasPar.Speed(12), Tool.PtMeasPar.Accel(60), "
      "Tool.PtMeasPar.Approach(10), Tool.PtMeasPar.Retract(2))");
  const std::string program[3] = {"GoTo(X(70), Y(250), Z(-20))",
                                  "GoTo(X(10), Y(250), Z(-20))",
                                  "PtMeas(X(0), Y(250), Z(-20), IJK(1, 0, 0))"};
  std::vector<double> us;
  us.reserve(kLines);
  auto next = Clock::now();
  for (int i = 0; i < kLines; ++i) {
    next += std::chrono::milliseconds(1);
    std::this_thread::sleep_until(next);  // pacing at 1000 lines/s, not synchronisation
    const auto start = Clock::now();
    const ipp::Transaction t = c.call(program[i % 3]);
    us.push_back(std::chrono::duration<double, std::micro>(Clock::now() - start).count());
    if (!t.ok()) break;
  }
  c.call("EndSession()");
  return us;
}

double percentile(std::vector<double> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[static_cast<std::size_t>(p * static_cast<double>(v.size() - 1))];
}

void BM_IppProxyAddedLatency(benchmark::State& state) {
  cmmcomp::vc::IppTwinMachine machine(cmmcomp::dynamics::default_machine(), {});
  ipp::Session session(machine);
  ipp::ServerOptions so;
  so.port = 0;
  ipp::Server server(session, so);
  std::thread server_thread([&] { server.run(); });
  cmmcomp::compensation::MoveCompensator compensator;
  cmmcomp::serving::load_slots({cmmcomp::serving::ModelSlot{0, ""}}, compensator);
  cmmcomp::serving::IppProxyOptions po;
  po.listen_port = 0;
  po.upstream_port = server.port();
  cmmcomp::serving::IppProxy proxy(compensator, po);
  std::thread proxy_thread([&] { proxy.run(); });

  std::vector<double> direct, proxied;
  for (auto _ : state) {
    direct = timed_session(server.port());
    proxied = timed_session(proxy.port());
  }
  const double d50 = percentile(direct, 0.5), d99 = percentile(direct, 0.99);
  const double p50 = percentile(proxied, 0.5), p99 = percentile(proxied, 0.99);
  state.counters["direct_p50_us"] = d50;
  state.counters["direct_p99_us"] = d99;
  state.counters["proxied_p50_us"] = p50;
  state.counters["proxied_p99_us"] = p99;
  state.counters["added_p50_us"] = p50 - d50;
  state.counters["added_p99_us"] = p99 - d99;
  state.counters["corrected"] = static_cast<double>(proxy.counters().corrected);
  proxy.request_stop();
  proxy_thread.join();
  server.request_stop();
  server_thread.join();
}
BENCHMARK(BM_IppProxyAddedLatency)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
