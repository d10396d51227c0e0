#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# expect.sh STATUS REGEX -- COMMAND ARGS... — runs COMMAND and passes when it exits with STATUS
# and its output (stdout and stderr) matches the extended regular expression REGEX.
set -uo pipefail
want="$1"; regex="$2"; shift 2
[ "${1:-}" = "--" ] && shift
out="$("$@" 2>&1)"; got=$?
printf '%s\n' "$out"
[ "$got" -eq "$want" ] || { echo "expect: exit status $got, wanted $want" >&2; exit 1; }
grep -qE -- "$regex" <<<"$out" || { echo "expect: output does not match '$regex'" >&2; exit 1; }
echo "expect: exit $got and '$regex' as wanted"
