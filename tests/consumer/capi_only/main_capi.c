/* SPDX-License-Identifier: MIT */
/** @file The installed C ABI from C99: a missing model file is a clear error code. */
#include <cmmcomp/compensator.h>
#include <stdio.h>
#include <string.h>

int main(void) {
  cmmcomp_compensator* c = NULL;
  const int rc = cmmcomp_create_from_file("/nonexistent/model.json", &c);
  printf("cmmcomp %s: %s\n", cmmcomp_version(), cmmcomp_strerror(rc));
  return (rc != 0 && c == NULL && strlen(cmmcomp_strerror(rc)) > 0) ? 0 : 1;
}
