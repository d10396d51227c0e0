#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# run-length-test.sh --agent-bin AGENT --vc-bin VC --out DIR [--can IFACE] [--model LABEL[@Y]=PATH]...
#                    [-- VC ARGS]
#
# The length test at speed in one command: starts one cmmcomp-agent per --model (LABEL=PATH;
# none: one agent with the shipped default model, label "default"), runs cmmcomp-vc against all
# of them, and stops the agents. Modbus TCP on free loopback ports by default; with --can IFACE
# (inside scripts/uml-run.sh) the agents share IFACE with base ids 0x300, 0x310, ... Writes into
# DIR: length_error_y*.png (plots), length_test.txt (the table), length_test.json,
# length_test_points.csv (every point) and length_test_session[.LABEL[-yY]].mbtx (Modbus
# transcripts; -yY for a per-Y agent, --model LABEL@Y=PATH) or .log (candump logs)
# (docs/recordings.md). Prints the table. Exit status: cmmcomp-vc's (2 when
# an agent does not start).
set -euo pipefail
agent_bin=""; vc_bin=""; out=""; models=(); can=""
while [ $# -gt 0 ]; do
  case "$1" in
    --agent-bin) agent_bin="$2"; shift 2 ;;
    --vc-bin) vc_bin="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --model) models+=("$2"); shift 2 ;;
    --can) can="$2"; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '3,14p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "run-length-test: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [ -z "$agent_bin" ] || [ -z "$vc_bin" ] || [ -z "$out" ]; then
  echo "run-length-test: --agent-bin, --vc-bin and --out are required (see --help)" >&2
  exit 2
fi
mkdir -p "$out"
[ ${#models[@]} -gt 0 ] || models=("default=")

pids=()
cleanup() { for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; wait "$p" 2>/dev/null || true; done; }
trap cleanup EXIT

agent_args=()
n=0
for spec in "${models[@]}"; do
  label="${spec%%=*}"; path="${spec#*=}"
  log="$out/agent_${label}.log"
  started=""
  model_arg=()
  [ -z "$path" ] || model_arg=(--model "$path")
  for attempt in $(seq 0 19); do
    # Empty the log first: the agent's own redirection truncates it only once the shell has
    # forked, so a "listening on" left from an earlier run in DIR could be read as this agent's.
    : >"$log"
    if [ -n "$can" ]; then
      base=$(printf '0x%03X' $(( 0x300 + 16 * n )))
      # 1 s between a request's parts, not the 50 ms default: a virtual bus in a UML guest on a
      # loaded host can stall that long between frames the vc sends back to back.
      "$agent_bin" --can "$can" --can-base-id "$base" --can-part-timeout-ms 1000 \
        "${model_arg[@]}" >"$log" 2>&1 &
    else
      port=$(( 20000 + ($$ * 37 + n * 1009 + attempt * 131) % 25000 ))
      "$agent_bin" --modbus "tcp:127.0.0.1:$port" "${model_arg[@]}" >"$log" 2>&1 &
    fi
    pid=$!
    for _ in $(seq 100); do
      if grep -q "listening on" "$log"; then started=1; break; fi
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.05
    done
    if [ -n "$started" ]; then pids+=("$pid"); break; fi
    kill "$pid" 2>/dev/null || true; wait "$pid" 2>/dev/null || true
    [ -z "$can" ] && grep -q "in use" "$log" || break
  done
  if [ -z "$started" ]; then
    echo "run-length-test: agent '$label' did not start:" >&2; cat "$log" >&2; exit 2
  fi
  if [ -n "$can" ]; then
    agent_args+=(--agent "$label=can:$can:$base")
  else
    agent_args+=(--agent "$label=modbus:tcp:127.0.0.1:$port")
  fi
  n=$((n + 1))
done

common=("${agent_args[@]}" --csv "$out/length_test_points.csv" "$@")
"$vc_bin" "${common[@]}" --json >"$out/length_test.json"
ext=mbtx
[ -z "$can" ] || ext=log
"$vc_bin" "${common[@]}" --plot "$out" --record "$out/length_test_session.$ext" |
  tee "$out/length_test.txt"
exit "${PIPESTATUS[0]}"
