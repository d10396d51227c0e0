// SPDX-License-Identifier: MIT
/// @file Hot swap on the Cortex-M7 (QEMU mps2-an500): the SysTick interrupt calls before_approach
/// while the main loop publishes two models in turn into a StaticMoveCompensator. Every
/// interrupt's correction must be exactly model A's or model B's, as its model id says: a torn
/// model (a buffer overwritten while the interrupt reads it) would give neither.
#include <cinttypes>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstdio>

#include "board/board.h"
#include "default.hpp"

namespace {

using cmmcomp::Status;
using cmmcomp::compensation::Correction;
using cmmcomp::compensation::MoveRequest;
using Model = cmmcomp::compensation::Model<cmmcomp::PaperInputs, float>;

constexpr Model kModelA{cmmcomp::fuzzy::convert_model<float>(default_model)};
// Model B: A with 1 µm added to every rule's constant term of every output. The normalised
// firing strengths sum to 1, so B answers A + 1 µm (up to rounding): a clearly different model.
constexpr Model kModelB = [] {
  Model m = kModelA;
  for (int o = 0; o < 4; ++o) {
    for (int j = 0; j < Model::kRules; ++j) m.params.consequent(o, j, 0) += 1.0f;
  }
  return m;
}();

cmmcomp::compensation::StaticMoveCompensator<Model> compensator;
MoveRequest g_move;
Correction g_expected[3];  // by model id 1 (A) and 2 (B)
volatile bool g_in_publish = false;
volatile std::uint32_t g_calls = 0;
volatile std::uint32_t g_calls_in_publish = 0;
volatile std::uint32_t g_wrong = 0;

bool same(const Correction& a, const Correction& b) {
  return a.mpe_um == b.mpe_um && a.rpe_um == b.rpe_um && a.mae_um == b.mae_um &&
         a.rae_um == b.rae_um && a.correction_um[0] == b.correction_um[0] &&
         a.correction_um[1] == b.correction_um[1] && a.correction_um[2] == b.correction_um[2] &&
         a.flags == b.flags && a.sequence == b.sequence && a.model_id == b.model_id;
}

}  // namespace

extern "C" void board_systick_handler(void) {
  Correction out;
  const Status s = compensator.before_approach(g_move, out);
  g_calls = g_calls + 1;
  if (g_in_publish) g_calls_in_publish = g_calls_in_publish + 1;
  if (!cmmcomp::ok(s) || out.model_id < 1 || out.model_id > 2 ||
      !same(out, g_expected[out.model_id])) {
    g_wrong = g_wrong + 1;
  }
}

int main() {
  g_move.sequence = 42;
  g_move.axis = 1;
  g_move.direction = {0.0, 0.0, -1.0};
  g_move.pv_mm_s = 70.0;
  g_move.pa_mm_s2 = 200.0;
  g_move.pd_mm = 60.0;
  g_move.av_mm_s = 12.0;
  g_move.aa_mm_s2 = 60.0;
  g_move.ad_mm = 10.0;
  // The expected answers, computed with interrupts off through the same compensator.
  if (compensator.publish(1, kModelB, 2) != Status::kOk ||
      !cmmcomp::ok(compensator.before_approach(g_move, g_expected[2])) ||
      compensator.publish(1, kModelA, 1) != Status::kOk ||
      !cmmcomp::ok(compensator.before_approach(g_move, g_expected[1]))) {
    std::printf("hot swap: set-up failed\nhot swap: FAIL\n");
    return 1;
  }
  std::printf("hot swap: model A RAE %.6f um, model B RAE %.6f um\n",
              g_expected[1].rae_um,
              g_expected[2].rae_um);
  // An interrupt every 400 core cycles: many land inside a publish (a 6.6 kB copy).
  board_systick_start(399, 1);
  // Waits for what it needs (interrupts inside a publish), bounded so a broken timer fails.
  constexpr std::uint32_t kNeeded = 200;
  constexpr long kMaxPublishes = 200000;
  long publishes = 0;
  long refused = 0;
  while (g_calls_in_publish < kNeeded && publishes < kMaxPublishes) {
    const bool b = publishes % 2 == 0;
    g_in_publish = true;
    const Status s = compensator.publish(1, b ? kModelB : kModelA, b ? 2 : 1);
    g_in_publish = false;
    refused += s == Status::kOk ? 0 : 1;
    ++publishes;
  }
  board_systick_stop();
  const bool pass = g_calls_in_publish >= kNeeded && g_wrong == 0 && refused == 0;
  std::printf("hot swap: %ld publishes, %" PRIu32 " interrupt calls, %" PRIu32
              " inside a publish, %" PRIu32 " wrong, %ld refused\n",
              publishes,
              g_calls,
              g_calls_in_publish,
              g_wrong,
              refused);
  std::printf("hot swap: %s\n", pass ? "PASS" : "FAIL");
  return pass ? 0 : 1;
}
