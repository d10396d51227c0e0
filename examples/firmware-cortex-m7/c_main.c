/* SPDX-License-Identifier: MIT */
/** @file The firmware example in C (C99): the same main loop as main.cpp through the firmware
 * C ABI (cmmcomp/compensator_fw.h), with the model compiled into the image as C data
 * (data/models/default-float.c, written by cmmcomp-train export --c-source --scalar float).
 * No heap, no file system: the compensator is the library's static storage. */
#include <cmmcomp/compensator_fw.h>
#include <inttypes.h>
#include <stdio.h>

extern const cmmcomp_fw_model default_model_c;
extern const uint64_t default_model_c_id;

static cmmcomp_move_request move(uint32_t sequence, double pv, double pd, double av, double ad) {
  cmmcomp_move_request m = {0};
  m.sequence = sequence;
  m.axis = 2; /* Z */
  m.direction[2] = -1.0;
  m.pv_mm_s = pv;
  m.pa_mm_s2 = 200.0;
  m.pd_mm = pd;
  m.av_mm_s = av;
  m.aa_mm_s2 = 60.0;
  m.ad_mm = ad;
  return m;
}

int main(void) {
  int failures = 0;
  uint32_t axis;
  for (axis = 0; axis < CMMCOMP_MAX_AXES; ++axis) {
    const int code = cmmcomp_fw_publish(axis, &default_model_c, default_model_c_id);
    if (code != CMMCOMP_OK) {
      printf("c example: publish axis %" PRIu32 ": %d\n", axis, code);
      return 1;
    }
  }
  {
    const cmmcomp_move_request moves[3] = {
        move(1, 40, 40, 8, 5), move(2, 70, 60, 12, 10), move(3, 100, 80, 16, 15)};
    int i;
    for (i = 0; i < 3; ++i) {
      cmmcomp_correction c;
      const int code = cmmcomp_fw_before_approach(&moves[i], &c);
      if (code != CMMCOMP_OK) {
        printf("c example: move %" PRIu32 ": %d\n", moves[i].sequence, code);
        ++failures;
        continue;
      }
      printf("c example: move %" PRIu32 ": RAE %.3f um, correction z %+.3f um, model %016llx\n",
             c.sequence,
             c.rae_um,
             c.correction_um[2],
             (unsigned long long)c.model_id);
    }
  }
  printf("c example: %s\n", failures == 0 ? "done" : "FAILED");
  return failures == 0 ? 0 : 1;
}
