#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# live_can.sh AGENT REPLAY DATA_DIR WORKDIR — the hil replay over CAN; run inside the UML guest
# (scripts/uml-run.sh). For every can-*.log in DATA_DIR (model: the repository's
# data/models/default-y.json for *-default-y.log, else default.json, as tests/tools/replay/CMakeLists.txt
# chooses), starts cmmcomp-agent on vcan0
# and replays the recording against it twice: with cmmcomp-replay --live can:vcan0 (own raw
# socket, field-by-field report), and with can-utils (canplayer sends the request frames,
# candump -L captures the answers, compared with the recorded answers frame for frame).
set -euo pipefail
agent="$1"; replay="$2"; data="$3"; work="$4"
root="$(cd "$data/../../../.." && pwd)"
mkdir -p "$work"
pid=""; dump=""
cleanup() {
  for p in $pid $dump; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done
}
trap cleanup EXIT
# start_agent MODEL LOG [PART_TIMEOUT_MS]: cmmcomp-agent on vcan0 (heartbeats on: replay must
# skip them); sets pid.
start_agent() {
  "$agent" --can vcan0 --can-heartbeat-ms 100 --can-part-timeout-ms "${3:-50}" --model "$1" \
    >"$2" 2>&1 &
  pid=$!
  for _ in $(seq 100); do grep -q "listening on" "$2" && break; sleep 0.05; done
  grep -q "listening on" "$2" || { cat "$2"; exit 1; }
}
count=0
for recording in "$data"/can-*.log; do
  name="$(basename "$recording" .log)"
  case "$name" in
    *-default-y) model="$root/data/models/default-y.json" ;;
    *) model="$root/data/models/default.json" ;;
  esac
  # The part timeout is part of what can-rejects.log records (its timeouts follow the recorded
  # timing); the other sessions' parts follow each other within a millisecond, and a loaded host
  # may stall the guest for longer than the 50 ms default: they get a generous timeout, which no
  # answer of theirs depends on. The test waits for what it needs, never for luck.
  timeout_ms=2000
  [ "$name" = "can-rejects" ] && timeout_ms=50
  start_agent "$model" "$work/agent-$name.log" "$timeout_ms"

  # 1. cmmcomp-replay's own raw socket (heartbeats are filtered out by its socket).
  "$replay" "$recording" --live can:vcan0 --quiet

  # 2. can-utils: the request frames only, replayed with their recorded timing, to a fresh agent
  # (reject frames carry the agent's reject count since it started).
  kill "$pid"; wait "$pid" 2>/dev/null || true; pid=""
  start_agent "$model" "$work/agent-$name-canplayer.log" "$timeout_ms"
  grep ' 300#' "$recording" >"$work/requests-$name.log"
  grep -E ' 30[12]#' "$recording" | cut -d' ' -f2- >"$work/expected-$name.txt"
  answers=$(wc -l <"$work/expected-$name.txt")
  candump -L -n "$answers" -T 3000 vcan0,301:7FF,302:7FF >"$work/captured-$name.log" &
  dump=$!
  sleep 0.2
  canplayer -I "$work/requests-$name.log"
  wait "$dump" || true; dump=""
  cut -d' ' -f2- "$work/captured-$name.log" >"$work/actual-$name.txt"
  if ! diff "$work/expected-$name.txt" "$work/actual-$name.txt"; then
    echo "live_can: canplayer replay of $recording: the answers differ (above: < recorded, > live)"
    exit 1
  fi
  echo "live_can: canplayer replay of $recording: $answers answer frames identical"
  kill "$pid"; wait "$pid" 2>/dev/null || true; pid=""
  count=$((count + 1))
done
[ "$count" -gt 0 ] || { echo "live_can: no can-*.log in $data"; exit 1; }
echo "live_can: $count recordings replayed live on vcan0"
