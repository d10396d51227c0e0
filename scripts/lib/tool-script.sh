# SPDX-License-Identifier: MIT
# Sourced by the measurement scripts that drive the built tools (cross-machine.sh,
# interval-coverage.sh): the tool check, the --check flag and the work folder, once.
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
