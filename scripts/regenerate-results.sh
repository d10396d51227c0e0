#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# regenerate-results.sh [BUILD_DIR] — re-runs every cmmcomp-study experiment whose section
# docs/results.md carries (docs/study.md, "The results page") and rewrites those sections. Run
# it from any folder after a change that moves a figure on purpose, then commit the page. The
# ctests run the same commands with --page and fail when a section is stale, so a command here
# must stay the ctest's (tests/tools/CMakeLists.txt).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${1:-$here/build/release}"
study="$build/tools/cmmcomp-study/cmmcomp-study"
if [ ! -x "$study" ]; then
  echo "regenerate-results: $study is not built (cmake --build --preset release)" >&2
  exit 2
fi
cd "$here"  # the commands on the page are relative to the checkout
page=docs/results.md
run() {  # run EXPERIMENT ARGS...: exit 1 (a target missed) still writes the section
  local status=0
  "$study" "$@" --page "$page" --update-page > /dev/null || status=$?
  if [ "$status" -gt 1 ]; then
    echo "regenerate-results: cmmcomp-study $1 failed (exit $status)" >&2
    exit "$status"
  fi
  [ "$status" = 0 ] || echo "regenerate-results: cmmcomp-study $1 misses a target (see the page)" >&2
}
run calibration --seeds 50 --seed 101 --known-unmet tests/data/calibration-known-unmet.txt
run identify-multistart
run accuracy --recipe data/recipes/paper-l18.toml --recipe data/recipes/default-y-model.toml \
  --known-unmet tests/data/accuracy-known-unmet.txt
run cell-interpolant --recipe data/recipes/paper-l18.toml \
  --recipe data/recipes/paper-l18-mode-20.toml --recipe data/recipes/paper-l18-drag+30.toml \
  --recipe data/recipes/paper-l18-y-participation+30.toml \
  --known-unmet tests/data/cell-interpolant-known-unmet.txt
run interval-coverage --model data/models/default.json --model-y data/models/default-y.json \
  --recipe data/recipes/default-model.toml --variant data/machines/variant-mode-20.toml \
  --variant data/machines/variant-drag+30.toml \
  --variant data/machines/variant-y-participation+30.toml \
  --known-unmet tests/data/interval-known-unmet.txt
cross_machine=(--machine default --machine data/machines/variant-mode-20.toml
  --machine data/machines/variant-drag+30.toml --machine data/machines/variant-y-participation+30.toml
  --dynamics-differ variant-mode-20 --dynamics-differ variant-drag+30
  --shipped data/models/default.json)
run cross-machine "${cross_machine[@]}"
run cross-machine "${cross_machine[@]}" --plan lhs162 --block cross-machine-lhs162
run interval-calibration --recipe data/recipes/default-model.toml \
  --plot docs/figures/interval-calibration.png
run qualified-sweep --model data/models/default-y.json
run cycle-speedup --machine default --machine data/machines/variant-mode-20.toml \
  --machine data/machines/variant-drag+30.toml \
  --machine data/machines/variant-y-participation+30.toml \
  --machine data/machines/variant-modes.toml --identify-from data/machines/default-start.toml
echo "regenerate-results: $page is current"
