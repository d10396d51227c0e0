/* SPDX-License-Identifier: MIT */
/** @file The C ABI from C99 (usage: test_capi DIR, DIR holding make_capi_models' output):
 * create from file and memory, before_approach numbers and signs, the 95 % interval
 * (before_approach_with_interval), error codes, hot reload that keeps the old model on failure,
 * destroy. Exits 0 when every check passes. */
#include <cmmcomp/compensator.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(cond)                                                            \
  do {                                                                         \
    if (!(cond)) {                                                             \
      fprintf(stderr, "%s:%d: check failed: %s\n", __FILE__, __LINE__, #cond); \
      ++failures;                                                              \
    }                                                                          \
  } while (0)

#define CHECK_NEAR(a, b) CHECK(fabs((a) - (b)) < 1e-12)

static char* read_all(const char* path, size_t* size) {
  FILE* f = fopen(path, "rb");
  char* buf = NULL;
  long n = 0;
  if (f == NULL) return NULL;
  if (fseek(f, 0, SEEK_END) == 0) n = ftell(f);
  if (n > 0 && fseek(f, 0, SEEK_SET) == 0) {
    buf = (char*)malloc((size_t)n);
    if (buf != NULL && fread(buf, 1, (size_t)n, f) != (size_t)n) {
      free(buf);
      buf = NULL;
    }
  }
  fclose(f);
  *size = (size_t)n;
  return buf;
}

static cmmcomp_move_request request(double pv_mm_s) {
  cmmcomp_move_request r;
  memset(&r, 0, sizeof r);
  r.sequence = 41u;
  r.axis = 2u;
  r.direction[2] = -1.0; /* probing downwards in z */
  r.pv_mm_s = pv_mm_s;
  r.pa_mm_s2 = 500.0;
  r.pd_mm = 20.0;
  r.av_mm_s = 5.0;
  r.aa_mm_s2 = 200.0;
  r.ad_mm = 2.0;
  r.y_mm = 250.0;
  r.z_mm = -80.0;
  return r;
}

int main(int argc, char** argv) {
  char path_a[4096];
  char path_b[4096];
  cmmcomp_compensator* c = NULL;
  cmmcomp_compensator* other = NULL;
  cmmcomp_move_request r;
  cmmcomp_correction out;
  cmmcomp_correction kept;
  cmmcomp_correction with_interval;
  cmmcomp_interval interval;
  cmmcomp_interval kept_interval;
  uint64_t id_a = 0;
  char* text_b = NULL;
  size_t size_b = 0;
  static const char corrupt[] = "{\"format\": \"cmmcomp-tsk-model\", \"format_version\": ";

  if (argc != 2) {
    fprintf(stderr, "usage: test_capi DIR\n");
    return 2;
  }
  snprintf(path_a, sizeof path_a, "%s/model_a.json", argv[1]);
  snprintf(path_b, sizeof path_b, "%s/model_b.json", argv[1]);

  CHECK(cmmcomp_abi_version() == CMMCOMP_ABI_VERSION);
  CHECK(cmmcomp_version() != NULL && strlen(cmmcomp_version()) <= CMMCOMP_MAX_MESSAGE_LENGTH);

  /* Errors of create: nothing is created. */
  CHECK(cmmcomp_create_from_file(NULL, &c) == CMMCOMP_E_ARGUMENT);
  CHECK(cmmcomp_create_from_file(path_a, NULL) == CMMCOMP_E_ARGUMENT);
  CHECK(cmmcomp_create_from_file("/nonexistent/model.json", &c) == CMMCOMP_E_IO);
  CHECK(cmmcomp_create_from_memory(corrupt, sizeof corrupt - 1, &c) == CMMCOMP_E_MODEL);
  CHECK(cmmcomp_create_from_memory("", 0, &c) == CMMCOMP_E_MODEL);
  CHECK(cmmcomp_create_from_memory(corrupt, CMMCOMP_MAX_MODEL_BYTES + 1u, &c) ==
        CMMCOMP_E_ARGUMENT);
  CHECK(c == NULL);

  /* Model A: y = c + k * (PV - 5)/75. PV = 42.5 mm/s gives x = 0.5. */
  CHECK(cmmcomp_create_from_file(path_a, &c) == CMMCOMP_OK);
  if (c == NULL) return 1;
  r = request(42.5);
  memset(&out, 0, sizeof out);
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_OK);
  CHECK_NEAR(out.mpe_um, 3.5);
  CHECK_NEAR(out.rpe_um, -1.0);
  CHECK_NEAR(out.mae_um, 4.0);
  CHECK_NEAR(out.rae_um, 3.5);
  /* Tip 3.5 um ahead of the scale while moving in -z: the touch point is 3.5 um lower. */
  CHECK(out.correction_um[0] == 0.0 && out.correction_um[1] == 0.0);
  CHECK_NEAR(out.correction_um[2], -3.5);
  CHECK(out.flags == CMMCOMP_FLAG_OK);
  CHECK(out.sequence == 41u);
  CHECK(out.model_id != 0u);
  id_a = out.model_id;

  /* The same request with its 95 % interval: the same correction, byte for byte, and U95 =
   * the calibrated half-widths inside the domain. */
  memset(&with_interval, 0xff, sizeof with_interval);
  CHECK(cmmcomp_before_approach_with_interval(c, &r, &with_interval, &interval) == CMMCOMP_OK);
  CHECK(memcmp(&with_interval, &out, sizeof out) == 0);
  CHECK_NEAR(interval.u95_um[0], 2.0);
  CHECK_NEAR(interval.u95_um[1], 1.5);
  CHECK_NEAR(interval.u95_um[2], 1.0);
  CHECK_NEAR(interval.u95_um[3], 0.5);
  CHECK(interval.flags == CMMCOMP_FLAG_OK);
  CHECK(interval.reserved == 0u);

  /* Outside the training domain: clamped (PV 86 -> 80, x = 1), flagged; the interval grows
   * with the distance d = (86 - 80)/75 = 0.08 ranges: U = h (1 + g d). */
  r = request(86.0);
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_OK);
  CHECK(out.flags == (CMMCOMP_FLAG_OK | CMMCOMP_FLAG_OUTSIDE_DOMAIN));
  CHECK_NEAR(out.rae_um, 4.5);
  CHECK(cmmcomp_before_approach_with_interval(c, &r, &with_interval, &interval) == CMMCOMP_OK);
  CHECK(interval.flags == (CMMCOMP_FLAG_OK | CMMCOMP_FLAG_OUTSIDE_DOMAIN));
  CHECK_NEAR(interval.u95_um[0], 2.0);
  CHECK_NEAR(interval.u95_um[1], 1.5 * (1.0 + 0.08));
  CHECK_NEAR(interval.u95_um[2], 1.0 * (1.0 + 2.0 * 0.08));
  CHECK_NEAR(interval.u95_um[3], 0.5 * (1.0 + 0.25 * 0.08));

  /* Far outside (more than 10 % of PV's range beyond it): refused although the C ABI clamps,
   * output untouched (docs/compensator.md, "Domain"). */
  r = request(200.0);
  memset(&with_interval, 0xff, sizeof with_interval);
  CHECK(cmmcomp_before_approach(c, &r, &with_interval) == CMMCOMP_E_OUTSIDE_DOMAIN_REJECTED);
  CHECK(with_interval.flags == 0xffffffffu);

  /* Invalid requests: error code, output untouched. */
  r = request(42.5);
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_OK);
  kept = out;
  r.pv_mm_s = nan("");
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_E_INVALID_INPUT);
  r = request(42.5);
  r.ad_mm = -1.0;
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_E_INVALID_INPUT);
  r = request(42.5);
  r.direction[0] = 0.5;
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_E_INVALID_INPUT);
  r = request(42.5);
  r.axis = CMMCOMP_MAX_AXES;
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_E_INVALID_INPUT);
  CHECK(cmmcomp_before_approach(NULL, &r, &out) == CMMCOMP_E_ARGUMENT);
  CHECK(cmmcomp_before_approach(c, NULL, &out) == CMMCOMP_E_ARGUMENT);
  CHECK(cmmcomp_before_approach(c, &r, NULL) == CMMCOMP_E_ARGUMENT);
  CHECK(memcmp(&out, &kept, sizeof out) == 0);
  /* The interval variant: the same codes, both outputs untouched. */
  kept_interval = interval;
  r.pv_mm_s = nan("");
  CHECK(cmmcomp_before_approach_with_interval(c, &r, &out, &interval) == CMMCOMP_E_INVALID_INPUT);
  r = request(42.5);
  CHECK(cmmcomp_before_approach_with_interval(c, &r, &out, NULL) == CMMCOMP_E_ARGUMENT);
  CHECK(cmmcomp_before_approach_with_interval(c, &r, NULL, &interval) == CMMCOMP_E_ARGUMENT);
  CHECK(cmmcomp_before_approach_with_interval(NULL, &r, &out, &interval) == CMMCOMP_E_ARGUMENT);
  CHECK(memcmp(&out, &kept, sizeof out) == 0);
  CHECK(memcmp(&interval, &kept_interval, sizeof interval) == 0);

  /* Reload failures keep model A serving. */
  CHECK(cmmcomp_reload_from_file(c, "/nonexistent/model.json") == CMMCOMP_E_IO);
  CHECK(cmmcomp_reload_from_memory(c, corrupt, sizeof corrupt - 1) == CMMCOMP_E_MODEL);
  CHECK(cmmcomp_reload_from_memory(NULL, corrupt, sizeof corrupt - 1) == CMMCOMP_E_ARGUMENT);
  r = request(42.5);
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_OK);
  CHECK_NEAR(out.rae_um, 3.5);
  CHECK(out.model_id == id_a);

  /* Reload to model B (from memory), then back to A (from file). */
  text_b = read_all(path_b, &size_b);
  CHECK(text_b != NULL);
  if (text_b != NULL) {
    CHECK(cmmcomp_reload_from_memory(c, text_b, size_b) == CMMCOMP_OK);
    CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_OK);
    CHECK_NEAR(out.rae_um, -0.5);
    CHECK_NEAR(out.correction_um[2], 0.5);
    CHECK(out.model_id != id_a);
    /* Model B has no interval calibration: U95 reads 0, flagged as unknown (not as exact). */
    CHECK(cmmcomp_before_approach_with_interval(c, &r, &out, &interval) == CMMCOMP_OK);
    CHECK(interval.flags == (CMMCOMP_FLAG_OK | CMMCOMP_FLAG_NO_UNCERTAINTY));
    CHECK(out.flags == CMMCOMP_FLAG_OK);
    CHECK(interval.u95_um[0] == 0.0 && interval.u95_um[1] == 0.0 && interval.u95_um[2] == 0.0 &&
          interval.u95_um[3] == 0.0);
    CHECK(cmmcomp_create_from_memory(text_b, size_b, &other) == CMMCOMP_OK);
    cmmcomp_destroy(other);
    free(text_b);
  }
  CHECK(cmmcomp_reload_from_file(c, path_a) == CMMCOMP_OK);
  CHECK(cmmcomp_before_approach(c, &r, &out) == CMMCOMP_OK);
  CHECK(out.model_id == id_a);

  /* strerror: static, never null, distinct for the codes. */
  CHECK(strcmp(cmmcomp_strerror(CMMCOMP_OK), "ok") == 0);
  CHECK(strcmp(cmmcomp_strerror(CMMCOMP_E_IO), cmmcomp_strerror(CMMCOMP_E_MODEL)) != 0);
  CHECK(cmmcomp_strerror(-12345) != NULL);
  CHECK(strlen(cmmcomp_strerror(CMMCOMP_E_INVALID_INPUT)) <= CMMCOMP_MAX_MESSAGE_LENGTH);

  cmmcomp_destroy(c);
  cmmcomp_destroy(NULL);
  if (failures != 0) {
    fprintf(stderr, "test_capi: %d check(s) failed\n", failures);
    return 1;
  }
  puts("test_capi: ok");
  return 0;
}
