#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# README command 2 (and all of CI): install what is missing, then build and run every test:
# the release build with warnings as errors (all ctest labels), the ASan+UBSan build of the
# tests, the firmware builds (Cortex-M7 under qemu-system-arm, aarch64 under qemu-aarch64), the
# ThreadSanitizer on the concurrency tests and the libFuzzer smoke, after the clang-format check;
# clang-tidy (.clang-tidy) after the release build.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$here"
jobs="$(nproc)"
start=$(date +%s)

bash scripts/install-deps.sh test

# The format check first: it takes seconds, and a formatting slip should not wait 40 minutes of
# builds to be reported.
echo "== format check =="
bash scripts/check-format.sh

# stage TITLE PRESET [CTEST ARGS...]: configure, build and test one preset, timing it. With
# STAGE_TARGETS set, builds only those targets.
stage() {
  local title="$1" preset="$2"
  shift 2
  local t0
  t0=$(date +%s)
  echo "== $title =="
  cmake --preset "$preset"
  local targets=()
  for t in ${STAGE_TARGETS:-}; do targets+=(--target "$t"); done
  cmake --build --preset "$preset" -j "$jobs" "${targets[@]}"
  ctest --preset "$preset" "$@"
  echo "== $title: $(( $(date +%s) - t0 )) s =="
}

stage "release build, all tests" release -j "$jobs"
# clang-tidy over the libraries, plugins and tools, on the release build's compile commands.
t0=$(date +%s)
echo "== clang-tidy =="
bash scripts/clang-tidy.sh build/release
echo "== clang-tidy: $(( $(date +%s) - t0 )) s =="
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1 \
  stage "ASan + UBSan build, all tests" asan -j "$jobs"
stage "Cortex-M7 firmware (qemu-system-arm -M mps2-an500)" fw-cortex-m7 -j "$jobs"
bash scripts/firmware-figures.sh
stage "aarch64 Linux (qemu-aarch64): the core's unit tests and golden vectors" aarch64 -j "$jobs"
# The programs labelled concurrency: the compensators' hot swap, the Modbus server under many
# and hostile clients, the agent's reload on SIGHUP, the I++ server and the compensating proxy.
STAGE_TARGETS="test_move_compensator test_conditions test_static_compensator test_modbus_server test_agent_modbus test_ipp_conformance test_ipp_proxy" \
  TSAN_OPTIONS=halt_on_error=1:second_deadlock_stack=1 \
  stage "ThreadSanitizer: the concurrency tests" tsan -L concurrency -j "$jobs"
# Two targets at a time (one core each): each fuzzes for CMMCOMP_FUZZ_SECONDS.
stage "libFuzzer smoke: every target on its committed corpus" fuzz -j "$jobs"

echo "test-all: everything passed in $(( $(date +%s) - start )) s"
