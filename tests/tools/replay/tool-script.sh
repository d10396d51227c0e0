# SPDX-License-Identifier: MIT
# Sourced by the live replay test (tests/tools/replay/live_modbus.sh): the tool check, the
# --check flag, the work folder and starting an agent on a free port, once.
# require_tools SCRIPT TOOL...: exits 2 with a hint when a tool is not built.
require_tools() {
  local script="$1"
  shift
  for tool in "$@"; do
    if [ ! -x "$tool" ]; then
      echo "$script: build the tools first: cmake --build --preset release" >&2
      exit 2
    fi
  done
}
# parse_check_and_work [--check] [WORK]: sets check (0/1) and work (WORK, or a temporary folder
# removed at exit), and creates it.
parse_check_and_work() {
  check=0
  if [ "${1:-}" = "--check" ]; then
    check=1
    shift
  fi
  work="${1:-}"
  if [ -z "$work" ]; then
    work="$(mktemp -d)"
    trap 'rm -rf "$work"' EXIT
  fi
  mkdir -p "$work"
}
# start_modbus_agent AGENT LOG HOST [AGENT ARGS...]: starts cmmcomp-agent on a free Modbus TCP
# port of HOST (up to 20 pseudo-random ports) and waits for its "listening on"; sets agent_pid
# and agent_port. Returns 1 when it did not start (LOG says why); the caller stops the agent.
start_modbus_agent() {
  local agent="$1" log="$2" host="$3"
  shift 3
  agent_pid=""
  agent_port=""
  local attempt
  for attempt in $(seq 0 19); do
    agent_port=$((20000 + ($$ * 53 + attempt * 1013) % 30000))
    : >"$log"  # empty first: a "listening on" of an earlier run is not this agent's
    "$agent" --modbus "tcp:$host:$agent_port" "$@" >"$log" 2>&1 &
    agent_pid=$!
    for _ in $(seq 100); do
      grep -q "listening on" "$log" && return 0
      kill -0 "$agent_pid" 2>/dev/null || break
      sleep 0.05
    done
    kill "$agent_pid" 2>/dev/null || true
    wait "$agent_pid" 2>/dev/null || true
    agent_pid=""
  done
  return 1
}
