#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# clang-tidy with the checks .clang-tidy names, over the libraries, the plugins and the tools
# (their sources and the project headers they include), every finding an error. Needs a
# configured build with compile_commands.json (default build/release; the release preset writes
# it). Tests and benchmarks are not checked (gtest's and Google Benchmark's macros and names).
# Usage: bash scripts/clang-tidy.sh [BUILD_DIR]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build/release}"
if [ ! -f "$build/compile_commands.json" ]; then
  echo "clang-tidy: no $build/compile_commands.json: configure first (cmake --preset release)" >&2
  exit 2
fi
runner="$(command -v run-clang-tidy || command -v run-clang-tidy-14 || true)"
if [ -z "$runner" ]; then
  echo "clang-tidy: run-clang-tidy not found: bash scripts/install-deps.sh test installs it" >&2
  exit 2
fi
log="$(mktemp)"
trap 'rm -f "$log"' EXIT
build="$(cd "$build" && pwd)"
# The files to check, as a regular expression over compile_commands.json's absolute paths: the
# tools compile as one unity file each (tools/CMakeLists.txt), which includes their sources.
files="^($here/(src|tools|plugins/[a-z]+/src)/|$build/tools/.*/Unity/)"
# A unity file includes the tools' .cpp files by design: bugprone-suspicious-include is off.
if ! "$runner" -p "$build" -quiet -j "$(nproc)" -checks=-bugprone-suspicious-include "$files" \
  > "$log" 2>&1; then
  grep -E "(warning|error):" "$log" | sort -u >&2 || cat "$log" >&2
  echo "clang-tidy: FAIL (findings above; .clang-tidy names the checks)" >&2
  exit 1
fi
echo "clang-tidy: clean ($(grep -c '"file"' "$build/compile_commands.json") translation units in the build, those under src/ and plugins/*/src/ and the tools' unity files checked)"
