#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# check_layering.sh [--self-test] SOURCE_DIR — the folders are the architecture (docs/architecture.md): every
# file of a layer includes cmmcomp headers of its own layer and the layers below it only. A
# core header that reached into io, or io into the twin, fails here with the file and line,
# before it fails a firmware build or a consumer with only some components installed.
set -euo pipefail
if [[ "$1" == --self-test ]]; then
  # The check must catch a core header that includes io: plant one in a copy and expect it named.
  copy=$(mktemp -d)
  trap 'rm -rf "$copy"' EXIT
  mkdir -p "$copy/plugins" "$copy/tools"
  cp -r "$2/include" "$2/src" "$copy/"
  cp -r "$2/plugins/can" "$2/plugins/modbus" "$copy/plugins/"
  cp -r "$2/tools/serving" "$copy/tools/"
  echo '#include <cmmcomp/io/model_file.hpp>' >> "$copy/include/cmmcomp/status.hpp"
  if out=$(bash "$0" "$copy" 2>&1); then
    echo "check_layering: self-test FAIL: a core header including io passed" >&2
    exit 1
  fi
  if [[ "$out" != *"include/cmmcomp/status.hpp:"*": core includes cmmcomp/io/model_file.hpp (io)"* ]]; then
    echo "check_layering: self-test FAIL: the violation was not named: $out" >&2
    exit 1
  fi
  echo "check_layering: self-test PASS (a planted core -> io include is reported)"
  exit 0
fi
root="$1"
cd "$root"

# layer_of PATH: the layer a source file or an included header (cmmcomp/...) belongs to.
layer_of() {
  case "$1" in
    include/cmmcomp/io/* | src/io/* | cmmcomp/io/*) echo io ;;
    include/cmmcomp/dynamics/* | include/cmmcomp/doe/* | src/dynamics/* | src/doe/* \
      | cmmcomp/dynamics/* | cmmcomp/doe/*) echo twin ;;
    include/cmmcomp/training/* | src/training/* | cmmcomp/training/*) echo training ;;
    include/cmmcomp/measure/* | src/measure/* | cmmcomp/measure/*) echo measure ;;
    include/cmmcomp/planning/* | src/planning/* | cmmcomp/planning/*) echo planning ;;
    include/cmmcomp/ipp/* | src/ipp/* | cmmcomp/ipp/*) echo ipp ;;
    include/cmmcomp/vc/* | src/vc/* | cmmcomp/vc/*) echo vc ;;
    include/cmmcomp/study/* | src/study/* | cmmcomp/study/*) echo study ;;
    src/capi/*) echo capi ;;
    plugins/*/include/* | plugins/*/src/* | cmmcomp/plugins/*) echo plugins ;;
    tools/serving/*) echo serving ;;
    include/cmmcomp/* | cmmcomp/*) echo core ;;
    *) echo unknown ;;
  esac
}

# allowed LAYER: the layers a file of LAYER may include (its own and those below it).
allowed() {
  case "$1" in
    core) echo "core" ;;
    io) echo "core io" ;;
    twin) echo "core io twin" ;;
    training) echo "core io twin training" ;;
    measure) echo "core io twin ipp measure" ;;
    planning) echo "core io planning" ;;
    ipp) echo "core io ipp" ;;
    vc) echo "core io twin planning ipp vc" ;;
    study) echo "core io twin training measure planning ipp vc study" ;;
    capi) echo "core io" ;;
    plugins) echo "core plugins" ;;
    serving) echo "core io ipp plugins serving" ;;
  esac
}

files=$(find include src plugins/*/include plugins/*/src tools/serving \
          -type f \( -name '*.hpp' -o -name '*.h' -o -name '*.cpp' \) | sort)
checked=0
includes=0
violations=0
for file in $files; do
  layer=$(layer_of "$file")
  if [[ "$layer" == unknown ]]; then
    echo "check_layering: $file is in no layer (docs/architecture.md)" >&2
    violations=$((violations + 1))
    continue
  fi
  ok=" $(allowed "$layer") "
  checked=$((checked + 1))
  while IFS=: read -r line header; do
    [[ -z "$line" ]] && continue
    includes=$((includes + 1))
    target=$(layer_of "$header")
    if [[ "$ok" != *" $target "* ]]; then
      echo "check_layering: $file:$line: $layer includes $header ($target)" >&2
      violations=$((violations + 1))
    fi
  done < <(grep -n -o -E '^[[:space:]]*#[[:space:]]*include[[:space:]]*[<"]cmmcomp/[^>"]+' "$file" \
             | sed -E 's/^([0-9]+):.*[<"](cmmcomp\/.*)$/\1:\2/' || true)
done

# The umbrella header is the core's and must stay so.
if grep -n -E '#include <cmmcomp/(io|dynamics|doe|training)/' include/cmmcomp/cmmcomp.hpp >&2; then
  violations=$((violations + 1))
fi

if ((checked < 50 || includes < 100)); then
  echo "check_layering: only $checked files and $includes includes seen: wrong SOURCE_DIR?" >&2
  exit 1
fi
if ((violations > 0)); then
  echo "check_layering: FAIL ($violations violations in $checked files)" >&2
  exit 1
fi
echo "check_layering: PASS ($checked files, $includes cmmcomp includes, every one downwards)"
