#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest tool_usage_errors (issue 36 §6): every tool ends a usage error with status 2 and, for a
# misspelt option, names the closest one; a bad move value names the flag and its range; a
# machine value outside its plausible range is a warning on stderr, a plausible file is quiet.
# Usage: usage_errors.sh TOOLS_DIR WORK_DIR
set -euo pipefail
bin=$1 work=$2
rm -rf "$work" && mkdir -p "$work" && cd "$work"
expect_usage() {  # expect_usage PATTERN COMMAND...: status 2 and PATTERN on stderr
  local pattern=$1
  shift
  set +e
  "$@" > /dev/null 2> err.txt
  local status=$?
  set -e
  [ $status = 2 ] || { echo "FAIL: $* exited $status, not 2"; cat err.txt; exit 1; }
  grep -q -- "$pattern" err.txt || { echo "FAIL: $*: no '$pattern' in:"; cat err.txt; exit 1; }
}
for tool in sim train measure plan agent vc replay; do
  expect_usage "" "$bin/cmmcomp-$tool/cmmcomp-$tool" --no-such-option-at-all
done
expect_usage "did you mean '--pv'" "$bin/cmmcomp-sim/cmmcomp-sim" move --pvv 40
expect_usage "did you mean '--check'" "$bin/cmmcomp-agent/cmmcomp-agent" --chek
expect_usage "--pv: Value -40 not in range" "$bin/cmmcomp-sim/cmmcomp-sim" move --pv -40
expect_usage "'nan' is not a finite number" "$bin/cmmcomp-sim/cmmcomp-sim" move --pd nan
"$bin/cmmcomp-sim/cmmcomp-sim" machine -o plausible.toml > /dev/null
"$bin/cmmcomp-sim/cmmcomp-sim" move --machine plausible.toml > /dev/null 2> quiet.txt
[ ! -s quiet.txt ] || { echo "FAIL: a plausible machine file must be quiet"; cat quiet.txt; exit 1; }
sed 's/^mode_frequency_hz = [0-9.e+-]*/mode_frequency_hz = 80/' plausible.toml > stiff.toml
"$bin/cmmcomp-sim/cmmcomp-sim" move --machine stiff.toml > /dev/null 2> loud.txt
grep -q "^warning: stiff.toml: machine parameter 'structure.mode_frequency_hz' = 80 is outside its plausible range" loud.txt
echo "tool_usage_errors: PASS"
