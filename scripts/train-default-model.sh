#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerates the shipped models from their recipes (docs/study.md, "Recipes"):
#  - data/models/default.json, the model cmmcomp-agent serves without --model:
#    data/recipes/default-model.toml (the paper's 4-input network on the default digital twin
#    with Table 1 noise, L18 x 3 seed 1 + 270 Latin-hypercube moves seed 3; docs/training.md);
#  - data/models/default-y.json, the same with the carriage position Y as fifth input:
#    data/recipes/default-y-model.toml.
# Both describe the SIMULATED machine, not a real one, and record their training conditions
# (format 4, docs/model-file.md "Conditions"). The committed networks were trained in format 3,
# before the trainer's prior last changed, and later given their conditions with `cmmcomp-train
# conditions`; a retrain today is a slightly different network, within what the ctest
# default_model_retrain allows. Training is deterministic: two runs of a recipe give the same
# network (only trained_at, and with it the checksum and id, differ); the ctests
# default_model_retrain and *_model_reproducible retrain them this way and compare.
# Usage: bash scripts/train-default-model.sh [output.json [output-y.json]]
# (needs the release tools built). CMMCOMP_FIT_ARGS, if set, is appended to the 4-input
# training (e.g. "--interval-folds ridge": seconds instead of the fold networks' minute).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${1:-$here/data/models/default.json}"
out_y="${2:-$here/data/models/default-y.json}"
bin="${CMMCOMP_BIN:-$here/build/release/tools}"
study="$bin/cmmcomp-study/cmmcomp-study"
if [ ! -x "$study" ]; then
  echo "train-default-model: build the tools first: cmake --preset release &&" \
       "cmake --build --preset release --target cmmcomp-study" >&2
  exit 2
fi
# shellcheck disable=SC2086 # CMMCOMP_FIT_ARGS is a list of options
"$study" train --recipe "$here/data/recipes/default-model.toml" ${CMMCOMP_FIT_ARGS:-} -o "$out"
"$study" train --recipe "$here/data/recipes/default-y-model.toml" -o "$out_y"
