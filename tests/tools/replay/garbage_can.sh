#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# garbage_can.sh AGENT REPLAY RECORDING MODEL WORKDIR: issue 16, bad input at the process level,
# over CAN; run inside the UML guest (scripts/uml-run.sh). Starts cmmcomp-agent on vcan1 (CAN FD
# capable, so FD frames reach the bus too) and sends it bounded garbage with can-utils' cangen:
#   1. 20 000 frames on the request identifier with random lengths and payloads;
#   2. 5 000 frames on the request identifier mixing extended, FD, BRS, ESI and RTR frames;
#   3. 5 000 frames with random identifiers of every kind.
# Then waits out the part timeout and replays RECORDING live against the same agent: every
# answer must be the recorded one. The agent must still be running, its resident set must have
# grown by less than 4 MiB, and SIGTERM must stop it with status 0.
set -euo pipefail
agent="$1"; replay="$2"; recording="$3"; model="$4"; work="$5"
mkdir -p "$work"
log="$work/agent-garbage.log"
pid=""
cleanup() { [ -z "$pid" ] || { kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true; }; }
trap cleanup EXIT

rss_kb() { awk '/^VmRSS:/ { print $2 }' "/proc/$1/status"; }

# Generous: a loaded host may stall the guest between the parts of a good request.
part_timeout_ms=1000
"$agent" --can vcan1 --can-heartbeat-ms 100 --can-part-timeout-ms "$part_timeout_ms" \
  --model "$model" >"$log" 2>&1 &
pid=$!
for _ in $(seq 100); do grep -q "listening on" "$log" && break; sleep 0.05; done
grep -q "listening on" "$log" || { cat "$log"; exit 1; }
rss_before=$(rss_kb "$pid")

# -p 10: wait for room in the socket's queue instead of dropping frames, so the counts are sent.
cangen vcan1 -I 300 -L r -D r -g 0 -p 10 -n 20000
cangen vcan1 -I 300 -m -g 0 -p 10 -n 5000
cangen vcan1 -I r -m -g 0 -p 10 -n 5000

# An incomplete request left by the garbage expires within the part timeout; its reject is sent
# when it expires, before the replay listens.
sleep 1.5
kill -0 "$pid" || { echo "garbage_can: the agent died under garbage"; cat "$log"; exit 1; }
rss_after=$(rss_kb "$pid")

"$replay" "$recording" --live can:vcan1 --quiet
growth=$((rss_after - rss_before))
if [ "$growth" -ge 4096 ]; then
  echo "garbage_can: the agent grew from $rss_before kB to $rss_after kB under garbage"
  exit 1
fi
kill -TERM "$pid"
status=0
wait "$pid" || status=$?
pid=""
if [ "$status" -ne 0 ]; then
  echo "garbage_can: the agent exited with $status on SIGTERM"; cat "$log"; exit 1
fi
grep -E "can|CAN" "$log" | tail -n 3
echo "garbage_can: 30000 garbage frames; the agent served the recording after them" \
     "(RSS $rss_before -> $rss_after kB)"
