#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# planned-length-test.sh --plan-bin PLAN --agent-bin AGENT --vc-bin VC --out DIR
#                        --model LABEL[@Y]=PATH [--model LABEL[@Y]=PATH]... [--plan-model PATH |
#                        --plan-model-at Y=PATH...] [--y LIST] [--edge-margin M] [--qualify]
#                        [--plan-arg ARG]... [-- MORE VC ARGS]
#
# The length test at the planner's settings (docs/planner.md): cmmcomp-plan finds, for the model
# --plan-model (default: the last --model), or a model per Y (--plan-model-at, repeated; the vc
# then takes one agent per Y with --model LABEL@Y=PATH), at the program's Y positions and the budget
# 0.5 × MPE_E(20 mm) (MPE_E = 1.9 + L/300 µm, the vc's), the fastest compensated setting and
# the fastest uncompensated setting that meet it. The length test
# (tools/cmmcomp-vc/run-length-test.sh) then probes fast at the compensated one and, as its
# reference, at the uncompensated one; when no uncompensated setting in the model's domain meets
# the budget it keeps the vc's fixed slow reference and says so. Writes DIR/plan.txt,
# DIR/plan.json, DIR/plan-settings.txt and the length test's files; prints both tables. Give the
# carriage positions with --y (to the planner and the vc both), not after --. --y defaults to
# 0,250,500, the vc's program, also with --plan-model-at (unlike cmmcomp-plan alone, which then
# takes the models' Ys): the planner must judge the Ys the vc probes, so each needs a model.
# --qualify: the uncompensated machine as a CMM with a static reversal map and its probe
# qualified at the measuring setting (docs/planner.md, "The qualified reference"): the vc
# measures the map first (cmmcomp-vc --qualify --map-only, with the same MORE VC ARGS), the
# planner judges the uncompensated setting by what map and qualification leave, and the length
# test's uncompensated columns are qualified the same way (-q). Needs a model that sees Y.
# --plan-arg: one more argument for cmmcomp-plan (repeat it), e.g. the training conditions of
# a model file that does not record them (--trained-pa 200 --machine M.toml).
set -euo pipefail
plan_bin=""; agent_bin=""; vc_bin=""; out=""; models=(); plan_model=""; plan_at=(); y="0,250,500"
margin=(); qualify=0; more_plan=()
while [ $# -gt 0 ]; do
  case "$1" in
    --plan-bin) plan_bin="$2"; shift 2 ;;
    --agent-bin) agent_bin="$2"; shift 2 ;;
    --vc-bin) vc_bin="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --model) models+=("$2"); shift 2 ;;
    --plan-model) plan_model="$2"; shift 2 ;;
    --plan-model-at) plan_at+=(--model-at "$2"); shift 2 ;;
    --y) y="$2"; shift 2 ;;
    --edge-margin) margin=(--edge-margin "$2"); shift 2 ;;
    --qualify) qualify=1; shift ;;
    --plan-arg) more_plan+=("$2"); shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n '3,26p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "planned-length-test: unknown option '$1' (see --help)" >&2; exit 2 ;;
  esac
done
if [ -z "$plan_bin" ] || [ -z "$agent_bin" ] || [ -z "$vc_bin" ] || [ -z "$out" ] ||
   [ ${#models[@]} -eq 0 ]; then
  echo "planned-length-test: --plan-bin, --agent-bin, --vc-bin, --out and --model are required" >&2
  exit 2
fi
if [ -n "$plan_model" ] && [ ${#plan_at[@]} -gt 0 ]; then
  echo "planned-length-test: give --plan-model or --plan-model-at, not both" >&2
  exit 2
fi
[ -n "$plan_model" ] || [ ${#plan_at[@]} -gt 0 ] || plan_model="${models[-1]#*=}"
[ ${#plan_at[@]} -gt 0 ] || plan_at=(--model "$plan_model")
mkdir -p "$out"
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)"

plan_args=("${plan_at[@]}" --y "$y" --mpe-e 1.9,300 --length 20 --share 0.5 "${margin[@]}"
           "${more_plan[@]}")
qualified_vc=()
if [ $qualify -eq 1 ]; then
  # The map as the length test will measure it (same Y, seed and machine: the same touches).
  map_line="$("$vc_bin" --qualify --map-only --y "$y" "$@")"
  read -r -a map_args <<< "$map_line"
  echo "qualified reference: $map_line"
  plan_args+=("${map_args[@]}")
  qualified_vc=(--qualify)
fi
# The planner: its table and the settings as cmmcomp-vc takes them, then the same as JSON.
status=0
"$plan_bin" "${plan_args[@]}" --vc-settings "$out/plan-settings.txt" > "$out/plan.txt" || status=$?
cat "$out/plan.txt"
if [ $status -ne 0 ]; then
  [ $status -eq 1 ] && why="found no compensated setting" || why="failed"
  echo "planned-length-test: cmmcomp-plan $why (exit $status)" >&2
  exit 1
fi
"$plan_bin" "${plan_args[@]}" --json > "$out/plan.json"
setting() { sed -n "s/^$1=//p" "$out/plan-settings.txt"; }  # setting compensated|uncompensated
vc_args=(--fast "$(setting compensated)")
if [ -n "$(setting uncompensated)" ]; then
  vc_args+=(--slow "$(setting uncompensated)")
  echo "reference: the planner's fastest uncompensated setting"
else
  qualified_word=""; [ $qualify -eq 0 ] || qualified_word="qualified "
  echo "reference: the vc's fixed slow setting (no ${qualified_word}uncompensated setting in the" \
       "model's domain meets the budget)"
fi
echo
model_args=()
for m in "${models[@]}"; do model_args+=(--model "$m"); done
bash "$here/tools/cmmcomp-vc/run-length-test.sh" --agent-bin "$agent_bin" --vc-bin "$vc_bin" \
  --out "$out" "${model_args[@]}" -- "${vc_args[@]}" "${qualified_vc[@]}" --y "$y" "$@"
