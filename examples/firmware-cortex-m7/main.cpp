// SPDX-License-Identifier: MIT
/// @file The firmware example: a bare-metal main loop on QEMU's mps2-an500 (Cortex-M7) that
/// serves the shipped model in float from a StaticMoveCompensator, takes MoveRequests from a
/// table, calls before_approach for each, and prints the corrections (docs/firmware.md).
///
/// Run it:  cmake --preset fw-cortex-m7 && cmake --build build/fw-cortex-m7
///          qemu-system-arm -M mps2-an500 -nographic -monitor none -serial none
///              -semihosting-config enable=on,target=native
///              -kernel build/fw-cortex-m7/examples/firmware-cortex-m7/cmmcomp_fw_example.elf
///          (one command line), or: ctest --preset fw-cortex-m7 -R firmware_example -V
#include <cinttypes>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cstdio>

#include "board/board.h"
#include "default.hpp"  // data/models/default.hpp, written by cmmcomp-train export

namespace {

using cmmcomp::Status;
using cmmcomp::compensation::Correction;
using cmmcomp::compensation::MoveRequest;

// The model compiled into the image, converted to float at compile time (read-only memory), and
// checked at compile time: a model that could not be published does not build.
using Model = cmmcomp::compensation::Model<cmmcomp::PaperInputs, float>;
constexpr Model kModel{cmmcomp::fuzzy::convert_model<float>(default_model)};
static_assert(!cmmcomp::fuzzy::find_problem(kModel), "the compiled-in model is valid");

// Static storage (.bss): no heap anywhere in the image's compensation path.
cmmcomp::compensation::StaticMoveCompensator<Model> compensator;

// The model id is the first 16 hex digits of the model's checksum (docs/model-file.md).
constexpr std::uint64_t hex_id(const char* text) {
  std::uint64_t v = 0;
  for (int i = 0; i < 16; ++i) {
    const char c = text[i];
    v = v * 16 + static_cast<std::uint64_t>(c <= '9' ? c - '0' : c - 'a' + 10);
  }
  return v;
}

MoveRequest move(std::uint32_t sequence, double pv, double pd, double av, double ad, int sign) {
  MoveRequest m;
  m.sequence = sequence;
  m.axis = 0;
  m.direction = {static_cast<double>(sign), 0.0, 0.0};
  m.pv_mm_s = pv;
  m.pa_mm_s2 = 200.0;
  m.pd_mm = pd;
  m.av_mm_s = av;
  m.aa_mm_s2 = 60.0;
  m.ad_mm = ad;
  m.y_mm = 250.0;
  return m;
}

}  // namespace

int main() {
  std::printf("cmmcomp firmware example: Cortex-M7, float model %s (%u bytes in .rodata)\n",
              default_model_model_id,
              static_cast<unsigned>(sizeof kModel));
  for (int axis = 0; axis < 3; ++axis) {
    const Status s = compensator.publish(axis, kModel, hex_id(default_model_model_id));
    if (s != Status::kOk) {
      std::printf("publish axis %d: %s\n", axis, cmmcomp::to_string(s));
      return 1;
    }
  }
  // The moves a part program would announce: the paper's Table 3 corners, one move outside the
  // training ranges by less than kFarOutsideShare (clamped and flagged) and one corrupt request
  // (rejected, no correction).
  const MoveRequest moves[] = {
      move(1, 40, 40, 8, 5, +1),
      move(2, 100, 80, 16, 15, -1),
      move(3, 70, 60, 12, 10, +1),
      move(4, 100, 40, 16, 5, +1),
      move(5, 105, 60, 12, 10, +1),
      move(6, 0.0, 60, 12, 10, +1),
  };
  int failures = 0;
  for (const MoveRequest& m : moves) {
    Correction c;
    const Status s = compensator.before_approach(m, c);
    if (!cmmcomp::ok(s)) {
      std::printf("move %" PRIu32 ": no correction (%s)\n", m.sequence, cmmcomp::to_string(s));
      failures += m.sequence == 6 ? 0 : 1;
      continue;
    }
    std::printf("move %" PRIu32
                ": PV %5.1f PD %4.1f AV %4.1f AD %4.1f -> MPE %6.3f RPE %6.3f "
                "MAE %6.3f RAE %6.3f um, correction x %+.3f um, flags 0x%" PRIx32 "\n",
                c.sequence,
                m.pv_mm_s,
                m.pd_mm,
                m.av_mm_s,
                m.ad_mm,
                c.mpe_um,
                c.rpe_um,
                c.mae_um,
                c.rae_um,
                c.correction_um[0],
                c.flags);
  }
  std::printf("example: %s\n", failures == 0 ? "done" : "FAILED");
  return failures == 0 ? 0 : 1;
}
