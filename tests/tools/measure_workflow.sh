#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest tool_measure_workflow: the real-machine workflow (docs/measurement.md) as a user runs it, on
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
  --white-noise-um 0.3 --sync -o campaign/rec
grep -q ',sync$' campaign/rec/move-0001.tracker.csv
# The clean campaign: the clock from the sync markers, the controller timing measured; quiet.
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec -o campaign/dataset.csv \
  --plot campaign/summary.png 2>stderr.txt | tee extract.txt
[ -s campaign/summary.png ] && [ "$(head -c 4 campaign/summary.png | tail -c 3)" = PNG ]
[ ! -s stderr.txt ] || { cat stderr.txt; echo "a clean campaign must be quiet"; exit 1; }
grep -q '^extracted 54 of 54 moves' extract.txt
grep -q '^tracker clock: offset 37.000 ms, drift 100.0 ppm, from 54 sync markers' extract.txt
grep -q '^controller timing: dwell 1.12[89] s (measured' extract.txt
grep -q '"extracted": 54' campaign/dataset.csv.summary.json
# The machine file's timing agrees with the traces: used.
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec \
  --machine "$(dirname "$0")/../../data/machines/default.toml" -o given.csv | tee given.txt
grep -q '^controller timing: dwell 1.128 s (given' given.txt
# A wrong dwell is refused, naming the measured one; the report and summary are still written.
if "$measure" extract --plan campaign/plan.csv --recordings campaign/rec --dwell 1.2 \
  -o wrong.csv 2>wrong.txt; then echo "a wrong dwell must be refused"; exit 1; fi
grep -q "the controller's dwell is 1.12[89] s" wrong.txt
[ -s wrong.csv.report.csv ] && [ -s wrong.csv.summary.json ] && [ ! -e wrong.csv ]
# Usage errors exit 2.
set +e
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec --dwell -1 -o u.csv 2>/dev/null
[ $? = 2 ] || { echo "--dwell -1 must be a usage error"; exit 1; }
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec --dwell nan -o u.csv 2>/dev/null
[ $? = 2 ] || { echo "--dwell nan must be a usage error"; exit 1; }
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec --drift-ppm 1e6 -o u.csv 2>/dev/null
[ $? = 2 ] || { echo "--drift-ppm 1e6 must be a usage error"; exit 1; }
set -e
# A copied plan row is an error naming both lines.
{ cat campaign/plan.csv; tail -n 1 campaign/plan.csv; } > dup.csv
if "$measure" extract --plan dup.csv --recordings campaign/rec -o d.csv 2>dup.txt; then exit 1; fi
grep -q 'is also on line' dup.txt
# Trained with its campaign's summary: the model records the conditions it is valid in, quietly.
"$train" fit campaign/dataset.csv --campaign campaign/dataset.csv.summary.json \
  -o campaign/model.json 2>fit.err | tee fit.txt
[ ! -s fit.err ] || { cat fit.err; echo "a fit with its campaign must be quiet"; exit 1; }
grep -q '^conditions: PA 200 mm/s2, AA 60 mm/s2, dwell 1.1[23][0-9]* s, smoothing 0.09[0-9]* s, axis x, machine unknown, noise floor ' fit.txt
"$train" conditions campaign/model.json | grep -q 'format 4: conditions: PA 200 mm/s2'
# Without it, the fit warns that the model will not know its controller timing, and the planner
# refuses such a model unless given the timing.
"$train" fit campaign/dataset.csv -o bare.json 2>bare.err >/dev/null
grep -q "^warning: cmmcomp-train: the model will not record the controller's dwell" bare.err
plan=$bin/cmmcomp-plan/cmmcomp-plan
set +e
"$plan" --model bare.json --budget-um 3 > /dev/null 2>bare-plan.err
status=$?
set -e
[ $status = 2 ] && grep -q 'does not record the controller dwell' bare-plan.err
"$plan" --model campaign/model.json --budget-um 3 | tee plan.txt
grep -q "PA 200, AA 60 mm/s² (the model's: the highest it was trained at)" plan.txt
grep -q "dwell 1.1[23][0-9]* s, smoothing 0.09[0-9]* s (the model's)" plan.txt
# The held-out check on the machine's own moves: a verdict line, and an exit status that says it.
"$measure" plan --design l18 --repeats 3 --nominal 100,250,-50 --normal 1,0,0 --holdout 30 \
  -o withheld | tee withheld.txt
grep -q '^planned 30 held-out moves (lhs design, seed 2) to withheld/holdout' withheld.txt
cmp -s withheld/plan.csv campaign/plan.csv
"$sim" record --plan withheld/holdout/plan.csv --two-clocks --sync --white-noise-um 0.3 \
  -o withheld/rec > /dev/null
"$measure" extract --plan withheld/holdout/plan.csv --recordings withheld/rec -o holdout.csv
set +e
"$train" eval campaign/model.json holdout.csv --check > check.txt
status=$?
set -e
cat check.txt
if grep -q 'held-out check .*: PASS$' check.txt; then [ $status = 0 ]; else
  grep -q 'held-out check .*: FAIL: ' check.txt && [ $status = 1 ]
fi
"$sim" dataset --design lhs --samples 60 --noise --seed 2 -o test.csv
"$train" eval campaign/model.json test.csv | tee eval.txt
grep -q 'reduction' eval.txt
# A broken campaign: one move's files gone, one tracker file cut before the touch, one file cut
# inside its last number (no line end), one with a NUL byte.
rm campaign/rec/move-0001.tracker.csv
head -n 200 campaign/rec/move-0002.tracker.csv > cut.csv && mv cut.csv campaign/rec/move-0002.tracker.csv
head -c -3 campaign/rec/move-0003.tracker.csv > cut.csv && mv cut.csv campaign/rec/move-0003.tracker.csv
printf '0.5,\0\n' >> campaign/rec/move-0004.controller.csv
"$measure" extract --plan campaign/plan.csv --recordings campaign/rec \
  --machine "$(dirname "$0")/../../data/machines/default.toml" -o broken.csv | tee broken.txt
grep -q '^extracted 50 of 54 moves' broken.txt
grep -q '^1,skipped,.*a stream is missing' broken.csv.report.csv
grep -q '^2,skipped,' broken.csv.report.csv
grep -q '^3,skipped,.*the last line has no line end' broken.csv.report.csv
grep -q '^4,skipped,.*a NUL byte' broken.csv.report.csv
# One continuous session recording instead of files per move: the moves are found in it.
"$sim" record --plan campaign/plan.csv --two-clocks --clock-offset-ms 37 --drift-ppm 100 \
  --session --sync -o session
[ -e session/session.tracker.csv ] && [ ! -e session/move-0001.tracker.csv ]
"$measure" extract --plan campaign/plan.csv --recordings session \
  --machine "$(dirname "$0")/../../data/machines/default.toml" -o session.csv | tee session.txt
grep -q '^session .*: 54 of 54 planned moves found, tracker clock from 54 sync markers' session.txt
grep -q '^extracted 54 of 54 moves' session.txt
# Without the sync, the clock from the motion is refused with its effect on the parameters.
"$sim" record --plan campaign/plan.csv --two-clocks --clock-offset-ms 37 --drift-ppm 100 \
  --session -o nosync
if "$measure" extract --plan campaign/plan.csv --recordings nosync -o nosync.csv 2>nosync.txt; then
  echo "two clocks without a sync must be refused"; exit 1
fi
grep -q 'aligned from the motion alone' nosync.txt
# A stray row 20 000 s late is an error naming its row, at once.
{ cat session/session.controller.csv; echo "20100.0,100.0,0"; } > stray.csv && mv stray.csv session/session.controller.csv
if timeout 20 "$measure" extract --plan campaign/plan.csv --recordings session -o stray.csv 2>stray.txt; then exit 1; fi
grep -q 'the time jumps by' stray.txt
echo "tool_measure_workflow: PASS"
