// SPDX-License-Identifier: MIT
/// @file Instruction counts on the Cortex-M7 (QEMU mps2-an500 with -icount shift=0, where each
/// guest instruction advances the virtual clock by exactly 1 ns and SysTick counts the 25 MHz
/// core clock, so one tick is 40 instructions). Calibrated against a loop of known length. A
/// benchmark, not a test of speed: it prints figures and fails only when a call fails.
#include <cinttypes>
#include <cmath>
#include <cmmcomp/compensation/move_request.hpp>
#include <cstdio>

#include "board/board.h"
#include "components.hpp"

namespace {

constexpr int kCalls = 200;
constexpr double kInstructionsPerTick = 1e9 / BOARD_CORE_CLOCK_HZ;  // icount shift=0: 1 ns each

std::uint32_t elapsed_ticks(std::uint32_t start, std::uint32_t end) {
  return (start - end) & 0x00FFFFFFu;  // SysTick counts down
}

template <typename F>
double instructions_per_call(F&& call) {
  board_irq_disable();
  const std::uint32_t t0 = board_systick_value();
  for (int k = 0; k < kCalls; ++k) call(k);
  const std::uint32_t t1 = board_systick_value();
  board_irq_enable();
  return elapsed_ticks(t0, t1) * kInstructionsPerTick / kCalls;
}

cmmcomp::compensation::MoveRequest move_for(int k) {
  cmmcomp::compensation::MoveRequest m;
  m.sequence = static_cast<std::uint32_t>(k);
  m.axis = 0;
  m.pv_mm_s = 40.0 + 0.3 * k;  // across the range [40, 100]
  m.pa_mm_s2 = 200.0;
  m.pd_mm = 40.0 + 0.2 * k;
  m.av_mm_s = 8.0 + 0.04 * k;
  m.aa_mm_s2 = 60.0;
  m.ad_mm = 5.0 + 0.05 * k;
  return m;
}

}  // namespace

int main() {
  board_systick_start(0x00FFFFFFu, 0);
  int failures = 0;
  // Calibration: 100000 iterations of a 2-instruction loop (subs, bne) = 200000 instructions.
  const double loop = instructions_per_call([](int) {
                        std::uint32_t n = 100000;
                        __asm volatile("1: subs %0, %0, #1\n bne 1b" : "+r"(n)::"cc");
                      }) /
                      200000.0;
  std::printf("figures: calibration %.4f counted per executed instruction (1.0 expected)\n", loop);
  if (std::fabs(loop - 1.0) > 0.01) {
    std::printf("figures: the clock does not count instructions: run QEMU with -icount shift=0\n");
    ++failures;
  }
  failures += cmmcomp_fw_publish_double(0) == 0 ? 0 : 1;
  failures += cmmcomp_fw_publish_float(0) == 0 ? 0 : 1;
  double y[4];
  volatile double sink = 0.0;
  const double eval_d = instructions_per_call([&](int k) {
    const cmmcomp::compensation::MoveRequest m = move_for(k);
    const double x[4] = {m.pv_mm_s, m.pd_mm, m.av_mm_s, m.ad_mm};
    failures += cmmcomp_fw_evaluate_double(x, y) >= 0 ? 0 : 1;
    sink = sink + y[3];
  });
  const double eval_f = instructions_per_call([&](int k) {
    const cmmcomp::compensation::MoveRequest m = move_for(k);
    const double x[4] = {m.pv_mm_s, m.pd_mm, m.av_mm_s, m.ad_mm};
    failures += cmmcomp_fw_evaluate_float(x, y) >= 0 ? 0 : 1;
    sink = sink + y[3];
  });
  cmmcomp::compensation::Correction c;
  const double before_d = instructions_per_call([&](int k) {
    const cmmcomp::compensation::MoveRequest m = move_for(k);
    failures += cmmcomp_fw_before_approach_double(&m, &c) >= 0 ? 0 : 1;
    sink = sink + c.rae_um;
  });
  const double before_f = instructions_per_call([&](int k) {
    const cmmcomp::compensation::MoveRequest m = move_for(k);
    failures += cmmcomp_fw_before_approach_float(&m, &c) >= 0 ? 0 : 1;
    sink = sink + c.rae_um;
  });
  const double publish_f = instructions_per_call(
      [&](int k) { failures += cmmcomp_fw_publish_float(k % 4) == 0 ? 0 : 1; });
  // The move each call builds costs a few instructions too: measured on its own, subtracted.
  const double overhead = instructions_per_call([&](int k) {
    const cmmcomp::compensation::MoveRequest m = move_for(k);
    sink = sink + m.ad_mm;
  });
  std::printf(
      "figures: instructions per 4-output evaluation of the 81-rule model: double %.0f, "
      "float %.0f\n",
      eval_d - overhead,
      eval_f - overhead);
  std::printf("figures: instructions per before_approach: double %.0f, float %.0f\n",
              before_d - overhead,
              before_f - overhead);
  std::printf("figures: instructions per publish of the float model: %.0f\n", publish_f);
  std::printf("figures: baseline move planned in %.6f s\n", cmmcomp_fw_profile_duration());
  std::printf("figures: %s\n", failures == 0 ? "done" : "FAILED");
  return failures == 0 ? 0 : 1;
}
