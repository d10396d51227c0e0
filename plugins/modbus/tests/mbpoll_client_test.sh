#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# mbpoll (an outside Modbus client) against modbus_test_server, which serves the closed-form
# model of docs/protocol-modbus.md's worked example: MPE = 10 + 2x, RPE = -2 + x, MAE = 4 + 2x,
# RAE = 1.5 + x with x = (PV - 5)/75. Writes the request as a client that cannot use FC23 does
# (FC16 floats, then the sequence register), reads the result with FC04, checks the numbers and
# the exceptions 02 and 03, then stops the server with SIGTERM.
# Usage: mbpoll_client_test.sh MODBUS_TEST_SERVER MBPOLL
set -euo pipefail
server_exe=$1
mbpoll=$2
work=$(mktemp -d)
server_pid=
cleanup() {
  if [ -n "$server_pid" ] && kill -0 "$server_pid" 2>/dev/null; then kill "$server_pid"; fi
  rm -rf "$work"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

# The file exists before the server starts: the background job opens it only when it runs.
: >"$work/server.out"
"$server_exe" >"$work/server.out" 2>&1 &
server_pid=$!
port=
for _ in $(seq 100); do
  port=$(sed -n 's/^listening on \([0-9]*\).*/\1/p' "$work/server.out")
  [ -n "$port" ] && break
  kill -0 "$server_pid" 2>/dev/null || fail "server exited: $(cat "$work/server.out")"
  sleep 0.05
done
[ -n "$port" ] || fail "server did not print its port"
echo "server: $(head -1 "$work/server.out")"

# -0: PDU (0-based) addresses as in the document; -B: high word first; -1: once.
# mb OPTIONS... [-- VALUES...]: the host must come before the values to write.
mb() {
  local opts=()
  while [ $# -gt 0 ] && [ "$1" != "--" ]; do opts+=("$1"); shift; done
  [ $# -gt 0 ] && shift
  "$mbpoll" -m tcp -a 1 -p "$port" -0 -1 -o 2 "${opts[@]}" 127.0.0.1 ${1+--} "$@"
}

# check_values OUTPUT EXPECTED...: the "[addr]: value" lines of mbpoll's output equal EXPECTED
# (within 1e-5 relative; floats are binary32).
check_values() {
  local out=$1; shift
  local got
  # mbpoll shows a register above 32767 as "65435 (-101)": keep the signed reading.
  got=$(printf '%s\n' "$out" | sed -n 's/^\[[0-9]*\]:[[:space:]]*//p' |
        sed 's/^[0-9]* (\(-[0-9]*\))$/\1/' | tr '\n' ' ')
  awk -v got="$got" -v want="$*" 'BEGIN {
    n = split(got, g, " "); m = split(want, w, " ");
    if (n != m) { print "got " n " values (" got "), want " m " (" want ")"; exit 1 }
    for (i = 1; i <= n; ++i) {
      d = g[i] - w[i]; if (d < 0) d = -d; t = w[i] < 0 ? -w[i] : w[i];
      if (d > 1e-5 * (1 + t)) { print "value " i ": got " g[i] ", want " w[i]; exit 1 }
    }
  }' || fail "unexpected values"
}

# request SEQUENCE AXIS DX DY DZ PV PA PD AV AA AD Y Z
request() {
  local seq=$1 axis=$2; shift 2
  mb -r 0 -t 4 -- "$axis" 0 >/dev/null || fail "writing the axis"
  mb -B -r 2 -t 4:float -- "$@" >/dev/null || fail "writing the floats"
  mb -r 24 -t 4 -- "$seq" >/dev/null || fail "writing the sequence"
}

# 1. The worked example: PV 42.5 (x = 0.5), d = (0.6, 0, -0.8).
request 7 0 0.6 0 -0.8 42.5 200 20 5 50 2 250 -100
check_values "$(mb -r 1 -c 4 -t 3)" 7 0 1 0                  # sequence, status, flags, axis
check_values "$(mb -B -r 6 -c 7 -t 3:float)" 11 -1.5 5 2 1.2 0 -1.6
# Protocol version 2; the interval block: the test model has no calibration, so interval_flags
# is OK | NO_UNCERTAINTY (0x11 = 17) and every U95 reads 0 (unknown).
check_values "$(mb -r 0 -c 1 -t 3)" 2
check_values "$(mb -r 52 -c 2 -t 3)" 17 0
check_values "$(mb -B -r 54 -c 4 -t 3:float)" 0 0 0 0
echo "worked example: ok"

# 2. PV 20 (x = 0.2), d = (0, 0, -1): MPE 10.4, RPE -1.8, MAE 4.4, RAE 1.7, correction (0, 0, -1.7).
request 8 0 0 0 -1 20 300 30 4 40 1 100 50
check_values "$(mb -r 1 -c 4 -t 3)" 8 0 1 0
check_values "$(mb -B -r 6 -c 7 -t 3:float)" 10.4 -1.8 4.4 1.7 0 0 -1.7
echo "second request: ok"

# 3. No model on axis 2: status -101, flags NO_MODEL (8).
request 9 2 1 0 0 20 300 30 4 40 1 100 50
check_values "$(mb -r 1 -c 4 -t 3)" 9 -101 8 2
echo "no model: ok"

# 4. Exception 02 (illegal address) and 03 (negative PV); the last result stays.
if out=$(mb -r 62 -c 1 -t 3 2>&1); then fail "reading register 62 succeeded"; fi
grep -q "Illegal data address" <<<"$out" || fail "no exception 02: $out"
if out=$(mb -B -r 8 -t 4:float -- -5 2>&1); then fail "writing PV = -5 succeeded"; fi
grep -q "Illegal data value" <<<"$out" || fail "no exception 03: $out"
check_values "$(mb -r 1 -c 4 -t 3)" 9 -101 8 2
echo "exceptions: ok"

# 5. Model id of axis 0 (u64, four registers, most significant first): 0x0123456789ABCDEF.
check_values "$(mb -r 36 -c 4 -t 3)" 291 17767 -30293 -12817  # 0x0123 0x4567 0x89AB 0xCDEF
echo "model id: ok"

kill -TERM "$server_pid"
wait "$server_pid" || fail "server exit status $?"
server_pid=
grep -q "^stopped:" "$work/server.out" || fail "server did not stop cleanly: $(cat "$work/server.out")"
echo "PASS"
