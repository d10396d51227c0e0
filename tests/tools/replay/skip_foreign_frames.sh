#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# skip_foreign_frames.sh REPLAY RECORDING MODEL WORKDIR — copies a CAN RECORDING with a
# heartbeat page (base + 3) and a frame of another identifier inserted after its first frame,
# and checks that cmmcomp-replay skips and counts both and still matches every answer.
set -euo pipefail
replay="$1"; recording="$2"; model="$3"; work="$4"
mkdir -p "$work"
copy="$work/with-foreign-frames.log"
ts="$(head -n 1 "$recording" | cut -d' ' -f1)"
{
  head -n 1 "$recording"
  echo "$ts vcan0 303#0003000300000100"
  echo "$ts vcan0 123#DEADBEEF"
  tail -n +2 "$recording"
} >"$copy"
out="$("$replay" "$copy" --model "$model" --quiet)"
printf '%s\n' "$out"
grep -q "(every answer byte for byte); skipped 1 heartbeats, 1 other" <<<"$out" ||
  { echo "skip_foreign_frames: the heartbeat and the foreign frame were not skipped and counted" >&2; exit 1; }
