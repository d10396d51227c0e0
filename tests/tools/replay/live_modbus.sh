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
# shellcheck source=tool-script.sh
source "$(dirname "${BASH_SOURCE[0]}")/tool-script.sh"
log="$(mktemp "${TMPDIR:-/tmp}/replay-agent.XXXXXX")"
agent_pid=""
cleanup() {
  if [ -n "$agent_pid" ]; then kill "$agent_pid" 2>/dev/null || true; wait "$agent_pid" 2>/dev/null || true; fi
  rm -f "$log"
}
trap cleanup EXIT
if ! start_modbus_agent "$agent" "$log" "$host" --model "$model"; then
  echo "live_modbus: the agent did not start:" >&2; cat "$log" >&2; exit 1
fi
port="$agent_port"
"$replay" "$recording" --live "modbus:tcp:$host:$port"
