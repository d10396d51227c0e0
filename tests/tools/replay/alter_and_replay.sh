#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# alter_and_replay.sh REPLAY RECORDING MODEL WORKDIR LINE BYTE FIELD — copies RECORDING into
# WORKDIR, changes byte BYTE of the answer on line LINE (a Modbus ADU byte, or a CAN data byte)
# and checks that cmmcomp-replay then exits 1 and names FIELD in its report.
set -euo pipefail
replay="$1"; recording="$2"; model="$3"; work="$4"; line="$5"; byte="$6"; field="$7"
mkdir -p "$work"
# One file per (line, byte): the CAN tests alter the same recording and may run in parallel.
altered="$work/altered-l${line}b${byte}-$(basename "$recording")"
# Flip the lowest bit of the byte, keeping the file's hex case (bash only: no gawk needed).
flip() { local v=$(( 16#$1 ^ 1 )); if [[ "$1" =~ [A-F] || "$2" = upper ]]; then printf '%02X' "$v"; else printf '%02x' "$v"; fi; }
text="$(sed -n "${line}p" "$recording")"
[ -n "$text" ] || { echo "alter_and_replay: $recording has no line $line" >&2; exit 1; }
if [[ "$text" == \(* ]]; then            # candump: (TS) IFACE ID#DATA
  data="${text##*#}"
  new="${data:0:$((2 * byte))}$(flip "${data:$((2 * byte)):2}" upper)${data:$((2 * byte + 2))}"
  text="${text%#*}#$new"
else                                     # transcript: TS DIR XX XX ...
  read -r -a words <<<"$text"
  words[$((2 + byte))]="$(flip "${words[$((2 + byte))]}" lower)"
  text="${words[*]}"
fi
{ head -n $((line - 1)) "$recording"; printf '%s\n' "$text"; tail -n +$((line + 1)) "$recording"; } >"$altered"
if cmp -s "$recording" "$altered"; then echo "alter_and_replay: nothing was changed" >&2; exit 1; fi
diff "$recording" "$altered" || true
set +e
out="$("$replay" "$altered" --model "$model" --quiet 2>&1)"; status=$?
set -e
printf '%s\n' "$out"
[ "$status" -eq 1 ] || { echo "alter_and_replay: exit $status, wanted 1 (mismatch)" >&2; exit 1; }
grep -qE "first difference: byte $byte, $field" <<<"$out" ||
  { echo "alter_and_replay: the report does not name byte $byte ($field)" >&2; exit 1; }
grep -qE "MISMATCH at .*:$line " <<<"$out" ||
  { echo "alter_and_replay: the report does not name line $line" >&2; exit 1; }
echo "alter_and_replay: line $line byte $byte ($field) reported"
