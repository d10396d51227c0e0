/* SPDX-License-Identifier: MIT */
/* The committed golden-vector file, as read-only bytes of the image (path from CMake). */
  .section .rodata.cmmcomp_golden, "a"
  .global cmmcomp_golden_csv
  .global cmmcomp_golden_csv_end
cmmcomp_golden_csv:
  .incbin CMMCOMP_GOLDEN_CSV
cmmcomp_golden_csv_end:
  .byte 0
