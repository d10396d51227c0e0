#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest tool_measure_workflow: README's "From a real machine to a model" as a user runs it, on
# the twin: plan -> record (two clocks, offset, drift, noise) -> extract -> fit -> eval; then a
# recording with a move removed and one cut short must still extract, with those skipped and
# their reasons reported; and the same campaign as one continuous session recording.
# Usage: measure_workflow.sh TOOLS_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
measure=$bin/cmmcomp-measure/cmmcomp-measure sim=$bin/cmmcomp-sim/cmmcomp-sim
train=$bin/cmmcomp-train/cmmcomp-train
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$measure" plan --design l18 --repeats 3 --nominal 100,250,-50 --normal 1,0,0 -o campaign
grep -q '^00001 StartSession()$' campaign/plan.ipp
[ "$(grep -c ' PtMeas(' campaign/plan.ipp)" = 54 ]
"$sim" record --plan campaign/plan.csv --two-clocks --clock-offset-ms 37 --drift-ppm 100 \
  --white-noise-um 0.3 -o campaign/rec
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec \
  --machine "$(dirname "$0")/../../data/machines/default.toml" -o campaign/dataset.csv | tee extract.txt
grep -q '^extracted 54 of 54 moves' extract.txt
grep -q '^tracker clock: offset ' extract.txt
"$train" fit campaign/dataset.csv -o campaign/model.json
"$sim" dataset --design lhs --samples 60 --noise --seed 2 -o test.csv
"$train" eval campaign/model.json test.csv | tee eval.txt
grep -q 'reduction' eval.txt
# A broken campaign: one move's files gone, one tracker file cut before the touch.
rm campaign/rec/move-0001.tracker.csv
head -n 200 campaign/rec/move-0002.tracker.csv > cut.csv && mv cut.csv campaign/rec/move-0002.tracker.csv
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec \
  --machine "$(dirname "$0")/../../data/machines/default.toml" -o broken.csv | tee broken.txt
grep -q '^extracted 52 of 54 moves' broken.txt
grep -q '^1,skipped,.*a stream is missing' broken.csv.report.csv
grep -q '^2,skipped,' broken.csv.report.csv
# One continuous session recording instead of files per move: the moves are found in it.
"$sim" record --plan campaign/plan.csv --two-clocks --clock-offset-ms 37 --drift-ppm 100 \
  --session -o session
[ -e session/session.tracker.csv ] && [ ! -e session/move-0001.tracker.csv ]
"$measure" extract --plan campaign/plan.csv --recordings session \
  --machine "$(dirname "$0")/../../data/machines/default.toml" -o session.csv | tee session.txt
grep -q '^session .*: 54 of 54 planned moves found, tracker offset' session.txt
grep -q '^extracted 54 of 54 moves' session.txt
echo "tool_measure_workflow: PASS"
