#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Regenerates what the firmware builds compile in, from the shipped models (docs/firmware.md):
#   data/models/default.hpp, data/models/default-y.hpp   cmmcomp-train export of the models
#   data/models/default-float.hpp, default-float.c         the 4-input model in float (C++, C ABI)
#   tests/data/golden/default-models.csv                   the golden vectors, host results
# Run it whenever data/models/*.json change (scripts/train-default-model.sh), after building
# the release preset. The tests exported_model_headers_current and golden_vectors_host fail
# until it has been run.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
bin="${CMMCOMP_BUILD:-build/release}"
train="$bin/tools/cmmcomp-train/cmmcomp-train"
if [ ! -x "$train" ]; then
  echo "regenerate-firmware-data: build first: cmake --preset release && cmake --build build/release" >&2
  exit 2
fi
"$train" export data/models/default.json --header data/models/default.hpp --symbol default_model
"$train" export data/models/default-y.json --header data/models/default-y.hpp --symbol default_y_model
"$train" export data/models/default.json --header data/models/default-float.hpp \
  --symbol default_model_f --scalar float
"$train" export data/models/default.json --c-source data/models/default-float.c \
  --symbol default_model_c --scalar float
# The golden program includes the headers just written: rebuild it, then let it write the file.
cmake --build "$bin" --target golden_vectors
mkdir -p tests/data/golden
"$bin/tests/golden_vectors" --write tests/data/golden/default-models.csv
