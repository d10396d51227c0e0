#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# map_matches_twin.sh VC SIM: without noise, cmmcomp-vc's reversal map (--qualify --map-only) is
# the twin's RAE at the map's quasi-static setting (PV 20, PD 60, AV 1, AD 2) at each node, as
# cmmcomp-sim move computes it: the vc measures the map, it does not assume it.
set -euo pipefail
vc="$1"; sim="$2"
line="$("$vc" --qualify --map-only --no-noise --y 0,500 --sphere-y 250)"
echo "$line"
case "$line" in
  "--sphere-y 250 --reversal-map "*) ;;
  *) echo "map_matches_twin: FAIL: unexpected line"; exit 1 ;;
esac
nodes="${line#--sphere-y 250 --reversal-map }"
count=0
for node in ${nodes//,/ }; do
  y="${node%%=*}"; map="${node#*=}"
  twin="$("$sim" move --pv 20 --pa 200 --pd 60 --av 1 --aa 60 --ad 2 --y "$y" --json |
          sed -n 's/.*"rae_um": *\([-0-9.e+]*\).*/\1/p')"
  echo "Y $y: map $map µm, twin $twin µm"
  if ! awk -v a="$map" -v b="$twin" 'BEGIN { d = a - b; exit !(d < 1e-3 && d > -1e-3) }'; then
    echo "map_matches_twin: FAIL at Y $y"; exit 1
  fi
  count=$((count + 1))
done
# The nodes are the program's Y and the sphere's: 0, 250, 500.
[ "$count" -eq 3 ] || { echo "map_matches_twin: FAIL: $count nodes, expected 3"; exit 1; }
echo "map_matches_twin: PASS"
