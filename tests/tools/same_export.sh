#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# same_export.sh TRAIN MODEL.json SYMBOL COMMITTED.hpp SCRATCH.hpp: exports MODEL.json again and
# fails, with the fix, unless the result is byte-identical to the committed header.
set -euo pipefail
train="$1" model="$2" symbol="$3" committed="$4" scratch="$5"
"$train" export "$model" --header "$scratch" --symbol "$symbol" >/dev/null
if ! cmp -s "$committed" "$scratch"; then
  echo "$committed is not the export of $model: run scripts/regenerate-firmware-data.sh" >&2
  diff "$committed" "$scratch" | head -5 >&2
  exit 1
fi
echo "$committed is the export of $model"
