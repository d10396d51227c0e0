#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# regenerate-recordings.sh [BUILD_DIR] — rewrites the committed session recordings in
# tests/tools/replay/data/ (docs/recordings.md) with cmmcomp-vc --record against cmmcomp-agent and the
# committed models. Run it when the wire protocol or a committed model changes on purpose, then
# review `git diff tests/tools/replay/data` and commit. BUILD_DIR (default build/release) must hold
# built cmmcomp-agent and cmmcomp-vc (cmake --build BUILD_DIR --target cmmcomp-agent cmmcomp-vc).
#
# Modbus sessions run on loopback (free port); CAN sessions run inside the User-Mode Linux guest
# (scripts/uml-run.sh) on vcan0. Every run is seeded, so only the timestamps change between two
# regenerations (tests/tools/replay/README.md).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-$root/build/release}" && pwd)"
agent="$build/tools/cmmcomp-agent/cmmcomp-agent"
vc="$build/tools/cmmcomp-vc/cmmcomp-vc"
data="$root/tests/tools/replay/data"
for exe in "$agent" "$vc"; do
  [ -x "$exe" ] || { echo "regenerate-recordings: $exe not built" >&2; exit 2; }
done
mkdir -p "$data"
# The program of every recording: 3 lengths × 2 Y × 2 faces = 12 requests (24 transcript lines,
# 84 CAN frames: 3 request and 4 response frames each, CAN protocol version 2). Keep in sync with tests/tools/replay/README.md. The guest gets them in VC_ARGS.
vc_args=(--lengths 20,100,400 --y 0,250 --repeats 1 --seed 7)
# name → model file (relative to the repository)
models=("default=data/models/default.json" "default-y=data/models/default-y.json")

work="$(mktemp -d "${TMPDIR:-/tmp}/regenerate-recordings.XXXXXX")"
agent_pid=""
cleanup() {
  if [ -n "$agent_pid" ]; then kill "$agent_pid" 2>/dev/null || true; wait "$agent_pid" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT

# ---- Modbus TCP on loopback
for spec in "${models[@]}"; do
  name="${spec%%=*}"; model="$root/${spec#*=}"
  started=""
  for attempt in $(seq 0 19); do
    port=$(( 20000 + ($$ * 31 + attempt * 977) % 30000 ))
    : >"$work/agent.log"  # exists before the background job runs and opens it
    "$agent" --modbus "tcp:127.0.0.1:$port" --model "$model" >"$work/agent.log" 2>&1 &
    agent_pid=$!
    for _ in $(seq 100); do
      if grep -q "listening on" "$work/agent.log"; then started=1; break; fi
      kill -0 "$agent_pid" 2>/dev/null || break
      sleep 0.05
    done
    [ -n "$started" ] && break
    kill "$agent_pid" 2>/dev/null || true; wait "$agent_pid" 2>/dev/null || true; agent_pid=""
  done
  [ -n "$started" ] || { echo "regenerate-recordings: the agent did not start:" >&2; cat "$work/agent.log" >&2; exit 1; }
  "$vc" --modbus "tcp:127.0.0.1:$port" "${vc_args[@]}" --record "$data/modbus-$name.log" >/dev/null
  kill "$agent_pid"; wait "$agent_pid" 2>/dev/null || true; agent_pid=""
  echo "wrote $data/modbus-$name.log ($(wc -l <"$data/modbus-$name.log") lines)"
done

# ---- CAN on vcan0, inside the UML guest (one boot for every model)
# can-rejects.log: hand-made traffic the vc never sends — a request whose part 1 comes after the
# 50 ms part timeout (reject "timeout", then "missing part" twice), a frame with DLC 4 (reject
# "wrong DLC"), then a good request — played by canplayer with these gaps, so the replay's
# part timeout is driven by recorded timestamps.
cat >"$work/rejects.in" <<'FRAMES'
(0.000000) vcan0 300#00E8037017400600
(0.100000) vcan0 300#01102728C0030000
(0.101000) vcan0 300#0200003008000000
(0.150000) vcan0 300#04E80370
(0.200000) vcan0 300#04E8037017400600
(0.201000) vcan0 300#05102728C0030000
(0.202000) vcan0 300#0600003008000000
FRAMES
cat >"$work/can.sh" <<'GUEST'
set -euo pipefail
agent="$1"; vc="$2"; data="$3"; root="$4"; rejects="$5"; shift 5
read -r -a vc_args <<<"$VC_ARGS"
start_agent() {  # start_agent MODEL
  "$agent" --can vcan0 --can-heartbeat-ms 0 --model "$1" >"$data/.agent.log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do grep -q "listening on" "$data/.agent.log" && break; sleep 0.05; done
}
for spec in "$@"; do
  name="${spec%%=*}"; model="$root/${spec#*=}"
  # Heartbeats off: the vc's filter drops them anyway; fewer frames on the bus.
  start_agent "$model"
  "$vc" --can vcan0 "${vc_args[@]}" --record "$data/can-$name.log" >/dev/null
  kill "$pid"; wait "$pid" 2>/dev/null || true
  echo "wrote $data/can-$name.log ($(wc -l <"$data/can-$name.log") frames)"
done
start_agent "$root/data/models/default.json"
# 7 request frames and 7 answers (4 rejects, 3 response parts); ids 0x300-0x303.
candump -L -n 14 -T 3000 vcan0,300:7FC >"$data/can-rejects.log" &
dump=$!
sleep 0.2
canplayer -I "$rejects"
wait "$dump" || true
kill "$pid"; wait "$pid" 2>/dev/null || true
echo "wrote $data/can-rejects.log ($(wc -l <"$data/can-rejects.log") frames)"
rm -f "$data/.agent.log"
GUEST
VC_ARGS="${vc_args[*]}" bash "$root/scripts/uml-run.sh" --timeout 120 -- \
  bash "$work/can.sh" "$agent" "$vc" "$data" "$root" "$work/rejects.in" "${models[@]}"
