#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# README command 2 (and all of CI): install what is missing, then build and run every test:
# the release build with warnings as errors (all ctest labels), the ASan+UBSan build of the
# tests, the firmware builds (Cortex-M7 under qemu-system-arm, aarch64 under qemu-aarch64) and
# the clang-format check.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
jobs="$(nproc)"
start=$(date +%s)

bash scripts/install-deps.sh

echo "== release build, all tests =="
cmake --preset release
cmake --build --preset release -j "$jobs"
ctest --preset release -j "$jobs"

echo "== ASan + UBSan build, all tests =="
cmake --preset asan
cmake --build --preset asan -j "$jobs"
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  ctest --preset asan -j "$jobs"

echo "== Cortex-M7 firmware (qemu-system-arm -M mps2-an500): example, golden vectors, hot swap, figures =="
cmake --preset fw-cortex-m7
cmake --build --preset fw-cortex-m7 -j "$jobs"
ctest --preset fw-cortex-m7 -j "$jobs"
bash scripts/firmware-figures.sh

echo "== aarch64 Linux (qemu-aarch64): the core's unit tests and golden vectors =="
cmake --preset aarch64
cmake --build --preset aarch64 -j "$jobs"
ctest --preset aarch64 -j "$jobs"

echo "== format check =="
bash scripts/check-format.sh

echo "test-all: everything passed in $(( $(date +%s) - start )) s"
