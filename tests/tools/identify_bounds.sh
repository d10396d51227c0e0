#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest tool_sim_identify_bounds (issue 36 §2): identify never moves what the recordings fix (the
# controller timing is fixed by default: naming it free is an error until --fixed frees it), and
# a parameter that ends at its plausible bound is marked in the table and named in a warning.
# Usage: identify_bounds.sh SIM WORK_DIR
set -euo pipefail
sim=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
"$sim" machine -o true.toml
# A machine whose dominant mode is at 80 Hz, past the plausible 10-50 Hz of the table.
sed 's/^mode_frequency_hz = [0-9.e+-]*/mode_frequency_hz = 80/' true.toml > stiff.toml
grep -q '^mode_frequency_hz = 80' stiff.toml
"$sim" dataset --design l9 --machine stiff.toml -o measured.csv > /dev/null
if "$sim" identify measured.csv --free controller.dwell_s -o x.toml 2> both.txt; then
  echo "FAIL: the controller timing must be fixed by default"; exit 1
fi
grep -q 'is both free and fixed' both.txt
"$sim" identify measured.csv --free structure.mode_frequency_hz --max-iterations 30 \
  -o fitted.toml > table.txt 2> warnings.txt
grep -q 'structure.mode_frequency_hz .*AT PLAUSIBLE MAX' table.txt
grep -q '^warning: structure.mode_frequency_hz ended at its plausible maximum 50' warnings.txt
# The controller timing is untouched by a default identification.
grep '^dwell_s = ' true.toml > a.txt
grep '^dwell_s = ' fitted.toml > b.txt
cmp -s a.txt b.txt
echo "tool_sim_identify_bounds: PASS"
