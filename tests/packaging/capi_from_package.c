/* SPDX-License-Identifier: MIT */
/** @file Built by tests/packaging/package_debs.sh against the cmmcomp-dev package's headers and
 * pkg-config file: the installed C ABI serves the installed default model (argv[1]). */
#include <cmmcomp/compensator.h>
#include <math.h>
#include <stdio.h>

int main(int argc, char** argv) {
  if (argc != 2) return 2;
  cmmcomp_compensator* c = NULL;
  int rc = cmmcomp_create_from_file(argv[1], &c);
  if (rc != CMMCOMP_OK) {
    fprintf(stderr, "create: %s\n", cmmcomp_strerror(rc));
    return 1;
  }
  const cmmcomp_move_request move = {
      7, 0, {1.0, 0.0, 0.0}, 70.0, 200.0, 60.0, 12.0, 60.0, 10.0, 250.0, 0.0};
  cmmcomp_correction out;
  rc = cmmcomp_before_approach(c, &move, &out);
  cmmcomp_destroy(c);
  if (rc != CMMCOMP_OK || out.sequence != 7 || !isfinite(out.rae_um) ||
      out.correction_um[0] != out.rae_um) {
    fprintf(stderr, "before_approach: %s\n", cmmcomp_strerror(rc));
    return 1;
  }
  printf("cmmcomp %s from the package: RAE %.3f um, model %016llx\n",
         cmmcomp_version(),
         out.rae_um,
         (unsigned long long)out.model_id);
  return 0;
}
