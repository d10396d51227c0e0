#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# A fuzzing campaign on one target (docs/fuzzing.md):
#   bash scripts/fuzz.sh TARGET SECONDS [JOBS]
# TARGET is one of fuzz/fuzz_*.cpp without the extension (e.g. fuzz_model_file). Builds the fuzz
# preset if needed and runs the target's generated runner (fuzz/CMakeLists.txt names its corpus
# and dictionary) into build/fuzz/campaign/TARGET: new inputs stay there; copy the interesting
# ones to fuzz/corpus/ by hand. Prints libFuzzer's final stats (executions, exec/s, cov, ft). A
# crash leaves its reproducer as build/fuzz/campaign/TARGET-crash-* and exits non-zero; replay it
# with: build/fuzz/fuzz/TARGET FILE
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
usage="usage: fuzz.sh TARGET SECONDS [JOBS]"
target="${1:?$usage}"
seconds="${2:?$usage}"
jobs="${3:-1}"
if [ ! -f "fuzz/$target.cpp" ]; then
  echo "fuzz.sh: unknown target '$target'; the targets are:" $(cd fuzz && ls fuzz_*.cpp | sed 's/\.cpp$//') >&2
  exit 2
fi
cmake --preset fuzz >/dev/null
cmake --build --preset fuzz --target "$target"
args=(-max_total_time="$seconds")
if [ "$jobs" -gt 1 ]; then args+=(-fork="$jobs"); fi
WORK="$PWD/build/fuzz/campaign/$target" exec sh "build/fuzz/fuzz/run-$target.sh" "${args[@]}"
