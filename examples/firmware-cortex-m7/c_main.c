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
extern const cmmcomp_fw_interval_calibration default_model_c_interval;
extern const cmmcomp_fw_conditions default_model_c_conditions;

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
    const int code = cmmcomp_fw_publish_with_conditions(axis,
                                                        &default_model_c,
                                                        &default_model_c_interval,
                                                        &default_model_c_conditions,
                                                        default_model_c_id);
    if (code != CMMCOMP_OK) {
      printf("c example: publish axis %" PRIu32 ": %d\n", axis, code);
      return 1;
    }
  }
  {
    /* A corner of the training box, its centre, the opposite corner: the RAE interval is
     * h (1 + k) at a corner (corner share 1) and h at the centre (docs/uncertainty.md). */
    const cmmcomp_move_request moves[3] = {
        move(1, 40, 40, 8, 5), move(2, 70, 60, 12, 10), move(3, 100, 80, 16, 15)};
    const double corner_share[3] = {1.0, 0.0, 1.0};
    int i;
    for (i = 0; i < 3; ++i) {
      cmmcomp_correction c;
      cmmcomp_interval u;
      const int code = cmmcomp_fw_before_approach_with_interval(&moves[i], &c, &u);
      const double h = default_model_c_interval.half_width[3];
      const double expected = h * (1.0 + default_model_c_interval.corner_gain[3] * corner_share[i] +
                                   default_model_c_interval.extrapolation_gain[3] * 0.0);
      if (code != CMMCOMP_OK) {
        printf("c example: move %" PRIu32 ": %d\n", moves[i].sequence, code);
        ++failures;
        continue;
      }
      printf("c example: move %" PRIu32
             ": RAE %.3f um +- %.3f (U95), correction z %+.3f um, model %016llx\n",
             c.sequence,
             c.rae_um,
             u.u95_um[3],
             c.correction_um[2],
             (unsigned long long)c.model_id);
      if (u.u95_um[3] != expected || (u.flags & CMMCOMP_FLAG_NO_UNCERTAINTY) != 0u) {
        printf("c example: move %" PRIu32 ": U95 of RAE %.17g, expected %.17g\n",
               c.sequence,
               u.u95_um[3],
               expected);
        ++failures;
      }
    }
  }
  {
    /* The model was trained at PA 200 mm/s² (default_model_c_conditions): PA 201 is inside (1 %
     * tolerance), 210 outside and flagged, 1200 far outside and refused under every policy
     * (docs/compensator.md, "Domain"). */
    const double pa[3] = {201.0, 210.0, 1200.0};
    const int want_code[3] = {CMMCOMP_OK, CMMCOMP_OK, CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED};
    const uint32_t want_flags[3] = {
        CMMCOMP_FLAG_OK, CMMCOMP_FLAG_OK | CMMCOMP_FLAG_OUTSIDE_DOMAIN, 0u};
    int i;
    for (i = 0; i < 3; ++i) {
      cmmcomp_move_request m = move((uint32_t)(10 + i), 70, 60, 12, 10);
      cmmcomp_correction c;
      int code;
      m.pa_mm_s2 = pa[i];
      c.flags = 0u;
      code = cmmcomp_fw_before_approach(&m, &c);
      printf("c example: PA %.0f mm/s2: code %d, flags %" PRIu32 "\n", pa[i], code, c.flags);
      if (code != want_code[i] || (code == CMMCOMP_OK && c.flags != want_flags[i])) {
        printf("c example: PA %.0f mm/s2: expected code %d, flags %" PRIu32 "\n",
               pa[i],
               want_code[i],
               want_flags[i]);
        ++failures;
      }
    }
  }
  printf("c example: %s\n", failures == 0 ? "done" : "FAILED");
  return failures == 0 ? 0 : 1;
}
