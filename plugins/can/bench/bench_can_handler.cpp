// SPDX-License-Identifier: MIT
/// @file In-process cost of the CAN server's per-frame work (no socket): a whole request (three
/// frames in, three out, one compensator call; with WantInterval four out), a reject, and the
/// codec alone.
#include <benchmark/benchmark.h>

#include <cmmcomp/plugins/can_request_handler.hpp>

#include "can_test_frames.hpp"

namespace {

using namespace cmmcomp;
using namespace cmmcomp::plugins::can;
using cmmcomp::plugins::CanFrameBatch;
using cmmcomp::plugins::CanRequestHandler;

struct Setup {
  /// `want_interval`: the model is published with its interval calibration and every request
  /// sets WantInterval (protocol version 2).
  explicit Setup(bool want_interval = false) {
    if (want_interval) {
      (void)cmmcomp::test::publish_example(comp);
    } else {
      (void)comp.publish(0, cmmcomp::test::example_model(), cmmcomp::test::kExampleModelId);
    }
    for (std::uint32_t s = 0; s < 64; ++s) {
      compensation::MoveRequest m = cmmcomp::test::example_move();
      m.sequence = s;
      m.pv_mm_s = 5.0 + s;
      (void)encode_request(m, kDefaultBaseId, requests[s], nullptr, want_interval);
    }
  }
  compensation::MoveCompensator comp;
  std::array<RequestFrames, 64> requests;
};

// Three request frames → three response frames: decode, reassemble, before_approach, encode.
void BM_HandleRequest(benchmark::State& state) {
  Setup s;
  CanRequestHandler handler(s.comp, kDefaultBaseId, std::chrono::milliseconds(50));
  std::size_t n = 0;
  for (auto _ : state) {
    const RequestFrames& r = s.requests[n++ % 64];
    CanFrameBatch out;
    for (const Frame& f : r) handler.on_frame(f, 0, out);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HandleRequest);

// The same with WantInterval: the U95 of a calibrated model and a fourth response frame.
void BM_HandleRequestWithInterval(benchmark::State& state) {
  Setup s(true);
  CanRequestHandler handler(s.comp, kDefaultBaseId, std::chrono::milliseconds(50));
  std::size_t n = 0;
  for (auto _ : state) {
    const RequestFrames& r = s.requests[n++ % 64];
    CanFrameBatch out;
    for (const Frame& f : r) handler.on_frame(f, 0, out);
    benchmark::DoNotOptimize(out);
  }
  state.SetItemsProcessed(state.iterations());
}
BENCHMARK(BM_HandleRequestWithInterval);

// A frame with a wrong DLC → one reject frame.
void BM_HandleWrongDlc(benchmark::State& state) {
  Setup s;
  CanRequestHandler handler(s.comp, kDefaultBaseId, std::chrono::milliseconds(50));
  Frame bad = s.requests[0][0];
  bad.dlc = 5;
  for (auto _ : state) {
    CanFrameBatch out;
    handler.on_frame(bad, 0, out);
    benchmark::DoNotOptimize(out);
  }
}
BENCHMARK(BM_HandleWrongDlc);

void BM_EncodeRequest(benchmark::State& state) {
  const compensation::MoveRequest m = cmmcomp::test::example_move();
  for (auto _ : state) {
    RequestFrames f;
    benchmark::DoNotOptimize(encode_request(m, kDefaultBaseId, f));
    benchmark::DoNotOptimize(f);
  }
}
BENCHMARK(BM_EncodeRequest);

void BM_DecodeRequest(benchmark::State& state) {
  RequestFrames f;
  (void)encode_request(cmmcomp::test::example_move(), kDefaultBaseId, f);
  const std::array<std::uint64_t, kRequestParts> w{
      load_word(f[0]), load_word(f[1]), load_word(f[2])};
  for (auto _ : state) {
    compensation::MoveRequest m;
    benchmark::DoNotOptimize(decode_request(w, 5, m));
    benchmark::DoNotOptimize(m);
  }
}
BENCHMARK(BM_DecodeRequest);

}  // namespace
