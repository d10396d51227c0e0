// SPDX-License-Identifier: MIT
/// @file libFuzzer target: before_approach of both compensators on arbitrary doubles, with the
/// shipped model. Invariants (abort on violation): a status is one of those documented; an ok
/// status writes finite values only, with the flags and echoes the request asks for; a failure
/// leaves `out` untouched; the hosted and the firmware compensator give the same answer.
#include <cmath>
#include <cmmcomp/compensation/move_compensator.hpp>
#include <cmmcomp/compensation/static_compensator.hpp>
#include <cmmcomp/io/default_model.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <cstring>

namespace {

using namespace cmmcomp;
using compensation::Correction;
using compensation::MoveRequest;

struct Compensators {
  compensation::MoveCompensator hosted;
  compensation::StaticMoveCompensator<compensation::Model<PaperInputs>> firmware;
  Compensators() {
    const auto file = io::default_model_file();
    for (int axis = 0; axis < 3; ++axis) {
      if (hosted.publish(axis, file.compensation_model(), 1) != Status::kOk) std::abort();
      if (firmware.publish(axis, file.model, 1) != Status::kOk) std::abort();
    }
  }
};

bool known(Status s) {
  switch (s) {
    case Status::kOk:
    case Status::kOutsideDomain:
    case Status::kInvalidInput:
    case Status::kNoModel:
    case Status::kOutsideDomainRejected:
      return true;
    default:
      return false;
  }
}

bool finite(const Correction& c) {
  bool f = std::isfinite(c.mpe_um) && std::isfinite(c.rpe_um) && std::isfinite(c.mae_um) &&
           std::isfinite(c.rae_um);
  for (const double v : c.correction_um) f = f && std::isfinite(v);
  return f;
}

void check(Status s, const Correction& out, const Correction& before, const MoveRequest& move) {
  if (!known(s)) std::abort();
  if (!ok(s)) {
    if (std::memcmp(&out, &before, sizeof out) != 0) std::abort();  // touched on a failure
    return;
  }
  if (!finite(out) || out.sequence != move.sequence) std::abort();
  if ((out.flags & compensation::kFlagOk) == 0) std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static Compensators c;
  double v[12] = {};
  if (size < sizeof v + 5) return 0;
  std::memcpy(v, data, sizeof v);
  MoveRequest move;
  move.axis = data[sizeof v] % 5;  // 3 has no model, 4 is out of range
  std::memcpy(&move.sequence, data + sizeof v + 1, 4);
  move.direction = {v[0], v[1], v[2]};
  move.pv_mm_s = v[3];
  move.pa_mm_s2 = v[4];
  move.pd_mm = v[5];
  move.av_mm_s = v[6];
  move.aa_mm_s2 = v[7];
  move.ad_mm = v[8];
  move.y_mm = v[9];
  move.z_mm = v[10];
  if (v[11] > 0.0) {  // half of the cases: a unit direction, so that evaluation is reached
    const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (std::isfinite(n) && n > 0.0) move.direction = {v[0] / n, v[1] / n, v[2] / n};
  }
  Correction before;
  std::memset(&before, 0xA5, sizeof before);
  Correction a = before;
  Correction b = before;
  const Status sa = c.hosted.before_approach(move, a);
  const Status sb = c.firmware.before_approach(move, b);
  check(sa, a, before, move);
  check(sb, b, before, move);
  if (move.axis < 3 && (sa != sb || std::memcmp(&a, &b, sizeof a) != 0)) std::abort();
  return 0;
}
