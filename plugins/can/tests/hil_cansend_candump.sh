#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# HIL check with can-utils as the outside peer; runs inside scripts/uml-run.sh (real vcan0).
#   hil_cansend_candump.sh CAN_TEST_SERVER docs/protocol-can.md
# Starts the test server (closed-form example model) on vcan0, sends the document's worked
# examples (version 1, and version 2 with WantInterval: four response frames) and its reject
# examples with `cansend`, captures the bus with `candump -L`, and checks that the server's
# frames are exactly the document's, that the heartbeat carries the model id, the counters and
# protocol version 2, and that the server's counters agree.
set -euo pipefail
server="$1"
doc="$2"
work="$(mktemp -d)"
server_pid=""
dump_pid=""
fd_server_pid=""
cleanup() {
  [ -n "$dump_pid" ] && kill "$dump_pid" 2>/dev/null || true
  [ -n "$server_pid" ] && kill "$server_pid" 2>/dev/null || true
  [ -n "$fd_server_pid" ] && kill "$fd_server_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT
fail() {
  echo "FAIL: $*" >&2
  echo "--- candump -L vcan0:" >&2
  cat "$work/dump" >&2 || true
  echo "--- server:" >&2
  cat "$work/server.out" "$work/server.err" >&2 || true
  exit 1
}

# The fenced block after <!-- MARKER --> in the document.
block() {
  awk -v m="<!-- $1 -->" '$0 == m { f = 1; next }
    f && /^```/ { if (b) exit; b = 1; next }
    f && b { print }' "$doc"
}

block example:request | awk '{ print $3 }' >"$work/request"
block example:response | awk '{ print $3 }' >"$work/expected"
[ "$(wc -l <"$work/request")" -eq 3 ] || fail "no 3-frame example request in $doc"
[ "$(wc -l <"$work/expected")" -eq 3 ] || fail "no 3-frame example response in $doc"
block example:interval-request | awk '{ print $3 }' >"$work/interval-request"
block example:interval-response | awk '{ print $3 }' >"$work/interval-expected"
[ "$(wc -l <"$work/interval-request")" -eq 3 ] || fail "no 3-frame interval request in $doc"
[ "$(wc -l <"$work/interval-expected")" -eq 4 ] || fail "no 4-frame interval response in $doc"

# A part timeout of 500 ms (default 50 ms): each cansend is a new process, slow under UML and
# slower on a loaded CI machine; the example's three parts must not time out.
"$server" --interface vcan0 --heartbeat-ms 200 --part-timeout-ms 500 --max-seconds 60 \
  >"$work/server.out" 2>"$work/server.err" &
server_pid=$!
for _ in $(seq 100); do
  grep -q '^ready: SocketCAN vcan0, base id 0x300$' "$work/server.out" && break
  kill -0 "$server_pid" 2>/dev/null || fail "server did not start"
  sleep 0.05
done
grep -q '^ready:' "$work/server.out" || fail "server not ready after 5 s"

# Line-buffered, so that the file shows what candump has seen so far.
stdbuf -oL candump -L vcan0 >"$work/dump" &
dump_pid=$!
# candump listens once it has logged a heartbeat (sent every 200 ms).
for _ in $(seq 100); do
  grep -q ' vcan0 303#' "$work/dump" && break
  sleep 0.05
done
grep -q ' vcan0 303#' "$work/dump" || fail "candump saw no heartbeat within 5 s"

# 1. The worked examples: request in, response out (the second with WantInterval: 4 frames).
while read -r frame; do cansend vcan0 "$frame"; done <"$work/request"
sleep 0.1
while read -r frame; do cansend vcan0 "$frame"; done <"$work/interval-request"
sleep 0.1
cat "$work/interval-expected" >>"$work/expected"

# 2. The document's reject table, in its order: | `sent` ... | `answer` | why |
first_part="$(head -n 1 "$work/request")"
grep -E '^\| (`300#|part 0 alone)' "$doc" >"$work/rejects" || fail "no reject examples in $doc"
while IFS='|' read -r _ sent answer _; do
  answer="$(echo "$answer" | tr -d '` ')"
  echo "$answer" >>"$work/expected"
  case "$sent" in
    *'part 0 alone'*)
      cansend vcan0 "$first_part"
      sleep 0.7 ;;  # > part timeout: the server must reject on its own
    *'then parts 1 and 2'*)  # reserved bits are checked when the request is complete
      cansend vcan0 "$(echo "$sent" | sed -E 's/^[^`]*`([^`]*)`.*$/\1/')"
      cansend vcan0 "$(sed -n 2p "$work/request")"
      cansend vcan0 "$(sed -n 3p "$work/request")"
      sleep 0.1 ;;
    *)
      cansend vcan0 "$(echo "$sent" | sed -E 's/^[^`]*`([^`]*)`.*$/\1/')"
      sleep 0.1 ;;
  esac
done <"$work/rejects"
# Wait (≤ 10 s) until every expected answer and a heartbeat that counts them were captured.
want="$(wc -l <"$work/expected")"
for _ in $(seq 200); do
  got="$(grep -cE ' vcan0 30[12]#' "$work/dump" || true)"
  [ "$got" -ge "$want" ] && grep -Eq ' vcan0 303#[0-9A-F][08]03000200050021$' "$work/dump" && break
  sleep 0.05
done

kill -INT "$dump_pid"
wait "$dump_pid" 2>/dev/null || true
dump_pid=""
kill -TERM "$server_pid"
wait "$server_pid" || fail "server exited with status $?"
server_pid=""

# candump -L: "(seconds.micro) vcan0 ID#DATA"; the server's answers are ids 0x301 and 0x302.
awk '$2 == "vcan0" && ($3 ~ /^301#/ || $3 ~ /^302#/) { print $3 }' "$work/dump" >"$work/actual"
if ! diff -u "$work/expected" "$work/actual" >"$work/diff"; then
  cat "$work/diff" >&2
  fail "server frames differ from the document (expected vs candump)"
fi
echo "ok: $(wc -l <"$work/actual") frames as documented (example responses and rejects)"

# Heartbeat page 1 (low 3 bits of byte 0 = 001): model id of axis 0 = 0xC0FFEE01.
grep -Eq ' vcan0 303#[0-9A-F][19]0001EEFFC00000$' "$work/dump" ||
  fail "no heartbeat page 1 with model id 0xC0FFEE01"
# Page 0 after the requests: requests 3, answered 2, rejected 5 (→ 0500), model mask 1 and
# protocol version 2 (byte 7 = 0x21).
grep -Eq ' vcan0 303#[0-9A-F][08]03000200050021$' "$work/dump" ||
  fail "no heartbeat page 0 with requests 3, answered 2, rejected 5, model mask 1, version 2"
echo "ok: heartbeat with model id and counters"

counters="$(grep '^counters:' "$work/server.out")" || fail "no counters from the server"
for c in frames_in=13 requests=3 answered=2 intervals=1 rejected=5 malformed=4 timeouts=1 \
         ignored=0 send_errors=0; do
  case " $counters " in *" $c "*) ;; *) fail "server counters: want $c in '$counters'" ;; esac
done
echo "ok: $counters"

# CAN FD on vcan1: the same example as CAN FD frames (cansend ID##<flags><data>, flags 1 = bit
# rate switch) gets the same bytes back as CAN FD frames.
"$server" --interface vcan1 --fd 1 --heartbeat-ms 0 --part-timeout-ms 500 --max-seconds 60 \
  >"$work/fd-server.out" 2>"$work/fd-server.err" &
fd_server_pid=$!
for _ in $(seq 100); do
  grep -q '^ready: SocketCAN vcan1 (CAN FD), base id 0x300$' "$work/fd-server.out" && break
  kill -0 "$fd_server_pid" 2>/dev/null || fail "CAN FD server did not start: $(cat "$work/fd-server.err")"
  sleep 0.05
done
stdbuf -oL candump -L vcan1 >"$work/fd-dump" &
dump_pid=$!
sleep 0.5  # no heartbeat to wait for on this bus
while read -r frame; do cansend vcan1 "${frame/\#/##1}"; done <"$work/request"
for _ in $(seq 200); do
  [ "$(grep -c ' vcan1 301##' "$work/fd-dump" || true)" -ge 3 ] && break
  sleep 0.05
done
kill -INT "$dump_pid"
wait "$dump_pid" 2>/dev/null || true
dump_pid=""
kill -TERM "$fd_server_pid"
wait "$fd_server_pid" || fail "CAN FD server exited with status $?"
fd_server_pid=""
# ID##<flags nibble><data>: the server sets bit-rate switch (1); kernels from 6.x also show the
# FD-frame flag (4), so the nibble is 1 or 5.
awk '$2 == "vcan1" && $3 ~ /^30[12]##/ { print $3 }' "$work/fd-dump" >"$work/fd-seen"
grep -Evq '##[15]' "$work/fd-seen" && fail "CAN FD answer without bit-rate switch: $(cat "$work/fd-seen")"
head -n 3 "$work/expected" | sed 's/#/##/' >"$work/fd-expected"
sed -E 's/##[15]/##/' "$work/fd-seen" >"$work/fd-actual"
if ! diff -u "$work/fd-expected" "$work/fd-actual" >&2; then
  cat "$work/fd-dump" >&2
  fail "CAN FD answer differs from the document's example"
fi
echo "ok: CAN FD on vcan1: $(tr '\n' ' ' <"$work/fd-seen")"
