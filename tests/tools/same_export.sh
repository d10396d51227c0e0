#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# same_export.sh TRAIN MODEL.json SYMBOL COMMITTED SCRATCH [EXPORT OPTIONS...]: exports MODEL.json
# again (a header, or what the options ask for) and fails, with the fix, unless the result is
# byte-identical to the committed file.
set -euo pipefail
train="$1" model="$2" symbol="$3" committed="$4" scratch="$5"
shift 5
if [ $# -eq 0 ]; then set -- --header "$scratch"; else set -- "$@" "$scratch"; fi
"$train" export "$model" --symbol "$symbol" "$@" >/dev/null
if ! cmp -s "$committed" "$scratch"; then
  echo "$committed is not the export of $model: run scripts/regenerate-firmware-data.sh" >&2
  diff "$committed" "$scratch" | head -5 >&2
  exit 1
fi
echo "$committed is the export of $model"
