#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The Cortex-M7 figures of docs/firmware.md, from the fw-cortex-m7 build: per component the bytes
# of code (.text), read-only data (.rodata: the model) and zero-initialised data (.bss: the
# compensator's buffers); the worst-case stack of each entry point (-fstack-usage along the
# call graph of -fcallgraph-info=su); and the instruction counts, measured by running the
# figures image under qemu-system-arm -icount shift=0. Fails when the code of a component
# exceeds the issue's 16 KiB goal, or a figure cannot be measured.
#   bash scripts/firmware-figures.sh [BUILD_DIR]   (default build/fw-cortex-m7)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
build="${1:-build/fw-cortex-m7}"
dir="$build/tests/firmware/CMakeFiles"
image="$build/tests/firmware/cmmcomp_fw_figures.elf"
if [ ! -f "$image" ]; then
  echo "firmware-figures: build first: cmake --preset fw-cortex-m7 && cmake --build build/fw-cortex-m7" >&2
  exit 2
fi

echo "component            .text  .rodata   .data    .bss  worst stack of each entry point [bytes]"
status=0
for component in evaluate_double evaluate_float compensator_double compensator_float profile_extract; do
  obj="$dir/cmmcomp_fw_$component.dir/components.cpp.obj"
  ci="$dir/cmmcomp_fw_$component.dir/components.cpp.ci"
  read -r text rodata data bss < <(arm-none-eabi-size -A "$obj" | awk '
    $1 ~ /^\.text/ { t += $2 } $1 ~ /^\.rodata/ { r += $2 } $1 ~ /^\.data/ { d += $2 }
    $1 ~ /^\.bss/ { b += $2 }
    END { print t + 0, r + 0, d + 0, b + 0 }')
  # Worst stack: the deepest path from each exported cmmcomp_fw_* function through the call
  # graph, summing static frames; library leaves (memset, sqrt, ...) are named, not counted.
  stacks=$(awk '
    /^node:/ {
      match($0, /title: "[^"]*"/); title = substr($0, RSTART + 8, RLENGTH - 9)
      frame[title] = 0
      if (match($0, /[0-9]+ bytes \((static|dynamic|dynamic,bounded)\)/)) {
        split(substr($0, RSTART, RLENGTH), parts, " "); frame[title] = parts[1]; known[title] = 1
        if ($0 ~ /bytes \(dynamic\)/) unbounded[title] = 1
      }
    }
    /^edge:/ {
      match($0, /sourcename: "[^"]*"/); s = substr($0, RSTART + 13, RLENGTH - 14)
      match($0, /targetname: "[^"]*"/); t = substr($0, RSTART + 13, RLENGTH - 14)
      n[s]++; callee[s, n[s]] = t
    }
    function depth(f, seen,    k, d, best) {
      if (f in seen) { recursive = 1; return 0 }
      seen[f] = 1
      if (!(f in known)) { leaves[f] = 1; delete seen[f]; return 0 }
      if (f in unbounded) dynamic = 1
      best = 0
      for (k = 1; k <= n[f]; ++k) { d = depth(callee[f, k], seen); if (d > best) best = d }
      delete seen[f]
      return frame[f] + best
    }
    END {
      out = ""
      for (f in frame) {
        if (f !~ /(^|:)cmmcomp_fw_/) continue
        name = f; sub(/.*:/, "", name); sub(/^cmmcomp_fw_/, "", name)
        split("", seen); out = out " " name " " depth(f, seen)
      }
      lib = ""; for (l in leaves) lib = lib (lib == "" ? "" : ",") l
      if (recursive) out = out " RECURSIVE"
      if (dynamic) out = out " DYNAMIC"
      print out (lib == "" ? "" : " (+ " lib ")")
    }' "$ci")
  printf "%-19s %6d %8d %7d %7d %s\n" "$component" "$text" "$rodata" "$data" "$bss" "$stacks"
  if [ "$text" -gt 16384 ]; then
    echo "firmware-figures: $component has $text bytes of code, over the 16 KiB goal" >&2
    status=1
  fi
  case "$stacks" in *RECURSIVE*|*DYNAMIC*) echo "firmware-figures: $component: unbounded stack" >&2; status=1 ;; esac
done

echo
echo "whole figures image (all components, board support, newlib; bss includes the 64 KiB stack"
echo "and the heap region up to it, which the linker script reserves):"
arm-none-eabi-size "$image" | sed 's/^/  /'
echo
echo "instruction counts (qemu-system-arm -M mps2-an500 -icount shift=0):"
out=$(timeout 120 qemu-system-arm -M mps2-an500 -nographic -monitor none -serial none \
  -semihosting-config enable=on,target=native -icount shift=0 -kernel "$image")
echo "$out" | sed 's/^/  /'
echo "$out" | grep -q "figures: done" || status=1
exit $status
