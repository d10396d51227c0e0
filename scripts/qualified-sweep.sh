#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# qualified-sweep.sh [--model PATH] [--seeds LIST] [WORK]
#
# The length test's speed-up on a qualified machine, measured on the twin (docs/planner.md,
# "The qualified reference"): runs cmmcomp-vc --qualify at every setting of a grid (PV, PD, AV,
# AD; PA 200, AA 60) for every noise seed, and prints, per setting, its time per point and
# whether the qualified uncompensated columns and the compensated ones (the model's agent) met
# MPE_E at every Y for every seed. Then the fastest setting of each kind and their ratio: the
# headline's "X× less time per point than the fastest uncompensated setting that meets the same
# MPE_E", with the twin itself as the judge instead of the planner's bounds.
# Defaults: the shipped 5-input model, seeds 1,2,3,4,5, the grid PV 76.75 100, PD 40 50 60,
# AV 12 14 16, AD 5 6 7 8 9 10 (override with the environment: PV="…" PD="…" AV="…" AD="…").
# Needs the release tools built (CMMCOMP_BIN overrides build/release/tools). About 10 s.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${CMMCOMP_BIN:-$here/build/release/tools}"
vc="$bin/cmmcomp-vc/cmmcomp-vc"
agent="$bin/cmmcomp-agent/cmmcomp-agent"
# shellcheck source=lib/tool-script.sh
source "$here/scripts/lib/tool-script.sh"
require_tools qualified-sweep "$vc" "$agent"
model="$here/data/models/default-y.json"
seeds="1,2,3,4,5"
while [ $# -gt 0 ]; do
  case "$1" in
    --model) model="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    -h|--help) sed -n '3,14p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "qualified-sweep: unknown option '$1' (see --help)" >&2; exit 2 ;;
    *) break ;;
  esac
done
# WORK, or a temporary folder removed at exit (with the agent stopped).
work="${1:-}"
temporary=""
if [ -z "$work" ]; then
  work="$(mktemp -d)"
  temporary="$work"
fi
mkdir -p "$work"
pvs="${PV:-76.75 100}"; pds="${PD:-40 50 60}"; avs="${AV:-12 14 16}"; ads="${AD:-5 6 7 8 9 10}"

# One agent serves every run (its answers are the compensated column).
agent_pid=""
cleanup() {
  if [ -n "$agent_pid" ]; then kill "$agent_pid" 2>/dev/null || true; wait "$agent_pid" 2>/dev/null || true; fi
  [ -z "$temporary" ] || rm -rf "$temporary"
}
trap cleanup EXIT
if ! start_modbus_agent "$agent" "$work/agent.log" 127.0.0.1 --model "$model"; then
  echo "qualified-sweep: the agent did not start" >&2; cat "$work/agent.log" >&2; exit 2
fi
port="$agent_port"

echo "| PV mm/s | PD mm | AV mm/s | AD mm | time per point s | qualified uncompensated | compensated |"
echo "|---|---|---|---|---|---|---|"
n_seeds=$(echo "$seeds" | tr ',' '\n' | grep -c .)
results="$work/results.txt"
: > "$results"
for pv in $pvs; do for pd in $pds; do for av in $avs; do for ad in $ads; do
  unc=0; comp=0; time_s=""
  for seed in ${seeds//,/ }; do
    report="$work/report.txt"
    "$vc" --agent "model=modbus:tcp:127.0.0.1:$port" --qualify --seed "$seed" \
      --fast "pv=$pv,pd=$pd,av=$av,ad=$ad" > "$report"
    time_s="$(sed -n 's/^  fast: .*(\([0-9.]*\) s per point, compensated)$/\1/p' "$report")"
    # The per-Y summary: Y, slow-q max and pass, fast-unc-q max and pass, fast-model max and pass.
    summary="$(awk '/^Per Y/ { on = 1; next } on && NF == 7 {
        u += ($5 == "pass"); c += ($7 == "pass"); n++ } END { if (n > 0) print (u == n), (c == n) }' "$report")"
    if [ -z "$time_s" ] || [ -z "$summary" ]; then
      echo "qualified-sweep: cannot read the vc's report at PV $pv PD $pd AV $av AD $ad:" >&2
      cat "$report" >&2
      exit 1
    fi
    read -r u c <<< "$summary"
    unc=$((unc + u)); comp=$((comp + c))
  done
  printf '| %s | %s | %s | %s | %s | %d of %d seeds pass | %d of %d seeds pass |\n' \
    "$pv" "$pd" "$av" "$ad" "$time_s" "$unc" "$n_seeds" "$comp" "$n_seeds"
  echo "$time_s $((unc == n_seeds)) $((comp == n_seeds)) PV $pv PD $pd AV $av AD $ad" >> "$results"
done; done; done; done

fastest() {  # fastest COLUMN: the fastest setting that passed every seed in column 2 or 3
  sort -g "$results" | awk -v col="$1" '$col == 1 { print; exit }'
}
describe() { echo "$1" | awk '{ printf "%s s per point at %s %s, %s %s, %s %s, %s %s", $1, $4, $5, $6, $7, $8, $9, $10, $11 }'; }
unc_best="$(fastest 2)"; comp_best="$(fastest 3)"
echo
echo "fastest qualified uncompensated setting that meets MPE_E (every Y, every seed):" \
     "$([ -n "$unc_best" ] && describe "$unc_best" || echo "none on the grid")"
echo "fastest compensated setting that meets MPE_E (every Y, every seed):" \
     "$([ -n "$comp_best" ] && describe "$comp_best" || echo "none on the grid")"
if [ -n "$unc_best" ] && [ -n "$comp_best" ]; then
  awk -v u="${unc_best%% *}" -v c="${comp_best%% *}" \
    'BEGIN { printf "qualified-sweep: compensation takes %.3fx less time per point (%.3f s against %.3f s)\n", u / c, c, u }'
fi
