#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# live_modbus.sh AGENT REPLAY RECORDING MODEL [HOST] — the hil replay over Modbus TCP on loopback:
# starts cmmcomp-agent with MODEL on a free port of HOST (default 127.0.0.1; "[::1]" for IPv6),
# sends every recorded request ADU of RECORDING to it (cmmcomp-replay --live) and checks every
# answer byte for byte.
set -euo pipefail
agent="$1"; replay="$2"; recording="$3"; model="$4"; host="${5:-127.0.0.1}"
if [ "$host" = "[::1]" ] && ! grep -q '^0\{31\}1 ' /proc/net/if_inet6 2>/dev/null; then
  echo "live_modbus: no IPv6 loopback on this machine (skipped)"
  exit 0
fi
log="$(mktemp "${TMPDIR:-/tmp}/replay-agent.XXXXXX")"
pid=""
cleanup() { if [ -n "$pid" ]; then kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; fi; rm -f "$log"; }
trap cleanup EXIT
for attempt in $(seq 0 19); do
  port=$(( 20000 + ($$ * 53 + attempt * 1013) % 30000 ))
  "$agent" --modbus "tcp:$host:$port" --model "$model" >"$log" 2>&1 &
  pid=$!
  for _ in $(seq 100); do
    grep -q "listening on" "$log" && break
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.05
  done
  grep -q "listening on" "$log" && break
  kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; pid=""
done
[ -n "$pid" ] || { echo "live_modbus: the agent did not start:" >&2; cat "$log" >&2; exit 1; }
"$replay" "$recording" --live "modbus:tcp:$host:$port"
