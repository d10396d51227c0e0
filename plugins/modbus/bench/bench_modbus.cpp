// SPDX-License-Identifier: MIT
/// @file Modbus TCP request → response on loopback against a server thread, with p50/p99 over
/// the run (counters p50_us, p99_us, max_us), and the in-process request handling alone.
///
/// Run: bench_modbus --benchmark_filter=Tcp (the TCP benchmarks run exactly 10 000 transactions).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmmcomp/plugins/modbus_request_handler.hpp>
#include <cstdint>
#include <vector>

#include "modbus_test_support.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins;
namespace map = cmmcomp::plugins::modbus;
using Clock = std::chrono::steady_clock;

constexpr int kTransactions = 10000;

/// Sets p50/p99/max counters [µs] from per-transaction times [ns].
void report(benchmark::State& state, std::vector<double>& ns) {
  std::sort(ns.begin(), ns.end());
  const auto at = [&](double q) {
    return ns[static_cast<std::size_t>(q * static_cast<double>(ns.size() - 1))] / 1000.0;
  };
  state.counters["p50_us"] = at(0.50);
  state.counters["p99_us"] = at(0.99);
  state.counters["max_us"] = ns.back() / 1000.0;
}

/// Publishes the example model on axis 0; false (and the benchmark marked failed) if it does not
/// validate.
bool publish_example(compensation::MoveCompensator& comp, benchmark::State& state) {
  if (comp.publish(0, test::example_model(), test::kExampleModelId) == Status::kOk) return true;
  state.SkipWithError("model does not validate");
  return false;
}

/// One transaction per iteration with sequence 1, 2, …: `prepare(sequence)` untimed, then
/// `transact(sequence)` timed (false: it failed, and the run stops); then the p50/p99/max
/// counters.
template <typename Prepare, typename Transact>
void time_transactions(benchmark::State& state, Prepare prepare, Transact transact) {
  std::vector<double> ns;
  ns.reserve(kTransactions);
  std::uint16_t sequence = 0;
  for (auto _ : state) {
    prepare(++sequence);
    const auto t0 = Clock::now();
    const bool good = transact(sequence);
    const auto t1 = Clock::now();
    if (!good) {
      state.SkipWithError("transaction failed");
      break;
    }
    ns.push_back(
        static_cast<double>(std::chrono::duration_cast<std::chrono::nanoseconds>(t1 - t0).count()));
  }
  if (!ns.empty()) report(state, ns);
}

/// The two-step transaction a simple client does: FC16 write of the whole request (sequence
/// last), then FC04 read of the result block.
void BM_TcpWriteThenReadResult(benchmark::State& state) {
  compensation::MoveCompensator comp;
  if (!publish_example(comp, state)) return;
  test::LoopbackServer server(comp);
  test::Client client = test::connect_client(server.port());
  map::HoldingRegisters h{};
  compensation::MoveRequest m = test::example_request();
  std::array<std::uint16_t, map::kResultWords> result{};
  time_transactions(
      state,
      [&](std::uint16_t sequence) {
        m.sequence = sequence;
        map::encode_request(m, h);
      },
      [&](std::uint16_t sequence) {
        const int w = modbus_write_registers(client.get(), 0, map::kRequestCount, h.data());
        const int r = modbus_read_input_registers(
            client.get(), map::kResultSequence, map::kResultWords, result.data());
        return w == map::kRequestCount && r == map::kResultWords && result[0] == sequence;
      });
}
BENCHMARK(BM_TcpWriteThenReadResult)->Iterations(kTransactions)->Unit(benchmark::kMicrosecond);

/// One round trip: FC23 writes the request and reads the result copy.
void BM_TcpReadWriteMultiple(benchmark::State& state) {
  compensation::MoveCompensator comp;
  if (!publish_example(comp, state)) return;
  test::LoopbackServer server(comp);
  test::Client client = test::connect_client(server.port());
  compensation::MoveRequest m = test::example_request();
  time_transactions(
      state,
      [&](std::uint16_t sequence) { m.sequence = sequence; },
      [&](std::uint16_t sequence) {
        map::Result r;
        return test::transact(client.get(), m, r) && r.sequence == sequence;
      });
}
BENCHMARK(BM_TcpReadWriteMultiple)->Iterations(kTransactions)->Unit(benchmark::kMicrosecond);

/// The per-request path alone: one triggering FC16 write (validation, compensator, staging).
void BM_HandleWriteRequest(benchmark::State& state) {
  compensation::MoveCompensator comp;
  if (!publish_example(comp, state)) return;
  ModbusRequestHandler handler(comp, 1, ModbusTransport::kTcp);
  const std::vector<std::uint8_t> adu = test::hex(test::kExampleWriteAdu);
  for (auto _ : state) {
    const ModbusDecision d = handler.handle(adu[6], adu.data() + 7, adu.size() - 7);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_HandleWriteRequest);

/// The per-request path alone: an FC04 read of every input register (status refresh).
void BM_HandleReadInputs(benchmark::State& state) {
  compensation::MoveCompensator comp;
  ModbusRequestHandler handler(comp, 1, ModbusTransport::kTcp);
  const std::uint8_t pdu[] = {kReadInputRegisters, 0, 0, 0, map::kInputCount};
  for (auto _ : state) {
    const ModbusDecision d = handler.handle(1, pdu, sizeof pdu);
    benchmark::DoNotOptimize(d);
  }
}
BENCHMARK(BM_HandleReadInputs);

}  // namespace
