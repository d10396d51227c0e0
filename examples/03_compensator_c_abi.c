/* SPDX-License-Identifier: MIT */
/** @file Example 3 (C99): the per-move compensator through its C ABI (cmmcomp::capi).
 *
 * Usage: 03_compensator_c_abi MODEL.json (e.g. the installed share/cmmcomp/models/default.json).
 * A controller creates one compensator at setup, then, before each approach, announces the move
 * and gets the predicted errors and the correction to ADD to the scale-reported touch point.
 * cmmcomp_before_approach is real-time safe (no allocation, no lock); create and destroy are not.
 * Self-check: the call succeeds, the result is finite and the correction is +RAE along d. */
#include <cmmcomp/compensator.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

int main(int argc, char** argv) {
  cmmcomp_compensator* comp = NULL;
  cmmcomp_move_request req;
  cmmcomp_correction out;
  int rc;
  int good;

  if (argc != 2) {
    fprintf(stderr, "usage: %s MODEL.json\n", argv[0]);
    return 2;
  }
  printf("cmmcomp %s, C ABI %u\n", cmmcomp_version(), cmmcomp_abi_version());

  /* Setup: read and validate the model file (4 inputs, or 5 with Y). */
  rc = cmmcomp_create_from_file(argv[1], &comp);
  if (rc != CMMCOMP_OK) {
    fprintf(stderr, "cannot load %s: %s\n", argv[1], cmmcomp_strerror(rc));
    return 1;
  }

  /* The paper's baseline move on the X axis (axis 0), probing in +X. Units are in the names. */
  memset(&req, 0, sizeof req);
  req.sequence = 7u;
  req.axis = 0u;
  req.direction[0] = 1.0;
  req.pv_mm_s = 40.0;
  req.pa_mm_s2 = 200.0;
  req.pd_mm = 40.0;
  req.av_mm_s = 12.0;
  req.aa_mm_s2 = 60.0;
  req.ad_mm = 10.0;
  req.y_mm = 250.0;
  req.z_mm = 0.0;

  /* Real time: predict before the approach starts. */
  rc = cmmcomp_before_approach(comp, &req, &out);
  if (rc != CMMCOMP_OK) {
    fprintf(stderr, "before_approach: %s\n", cmmcomp_strerror(rc));
    cmmcomp_destroy(comp);
    return 1;
  }
  printf("model %016llx, sequence %u, flags 0x%x\n",
         (unsigned long long)out.model_id,
         out.sequence,
         out.flags);
  printf("MPE %.3f um  RPE %.3f um  MAE %.3f um  RAE %.3f um\n",
         out.mpe_um,
         out.rpe_um,
         out.mae_um,
         out.rae_um);
  printf("correction to add to the touch point: (%.3f, %.3f, %.3f) um\n",
         out.correction_um[0],
         out.correction_um[1],
         out.correction_um[2]);

  good = (out.flags & CMMCOMP_FLAG_OK) != 0u && (out.flags & CMMCOMP_FLAG_OUTSIDE_DOMAIN) == 0u &&
         out.sequence == req.sequence && isfinite(out.rae_um) && out.mpe_um > 0.0 &&
         fabs(out.correction_um[0] - out.rae_um) < 1e-12 && out.correction_um[1] == 0.0 &&
         out.correction_um[2] == 0.0;

  cmmcomp_destroy(comp); /* setup only: no before_approach may be running */
  printf("%s\n", good ? "OK" : "WRONG");
  return good ? 0 : 1;
}
