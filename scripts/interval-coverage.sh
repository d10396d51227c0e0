#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The coverage of the shipped model's 95 % prediction interval (docs/uncertainty.md), measured:
#  - held out: 270 Latin-hypercube moves of the default twin with Table 1 noise, for three test
#    seeds (2, 4, 5; the model was trained on seeds 1 and 3, scripts/train-default-model.sh);
#  - unseen machines: the same 270 moves (seed 2) on the three variant machines
#    (data/machines/variant-*.toml) the model was never trained on;
#  - outside the domain: 270 moves over wider ranges (PV 30-130 mm/s, AD 3-20 mm), where the
#    out-of-domain flag and the extrapolation term must react.
# Coverage = share of moves whose measured value lies within predicted ± U95.
# With --check (the ctest accuracy_interval_coverage): exit 1 unless
#  - on every held-out seed, every parameter's coverage is >= 92 % (95 - 3: never under-covers);
#  - on seed 2 and pooled over the three seeds (810 moves; one set of 270 has a binomial
#    standard deviation of 1.3 points), every parameter not listed in
#    tests/data/interval-known-unmet.txt is <= 98 %, and every one listed there is still > 98 %
#    (the list cannot outlive its reason);
#  - outside the domain, moves are flagged, some parameter's mean U95 grows, and every
#    parameter's coverage is still >= 92 %;
#  - at the corners of the box (and of the box less 10 % of each range at both ends), every
#    parameter's coverage is >= 92 % for both shipped models: the corner gain at work
#    (docs/uncertainty.md; margin 0.2 is reported, not checked).
# Usage: bash scripts/interval-coverage.sh [--check] [WORK]   (needs the release tools built)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${CMMCOMP_BIN:-$here/build/release/tools}"
sim="$bin/cmmcomp-sim/cmmcomp-sim"
train="$bin/cmmcomp-train/cmmcomp-train"
model="$here/data/models/default.json"
known="$here/tests/data/interval-known-unmet.txt"
# shellcheck source=lib/tool-script.sh
source "$here/scripts/lib/tool-script.sh"
require_tools interval-coverage "$sim" "$train"
parse_check_and_work "$@"
# shellcheck source=lib/eval-json.sh
source "$here/scripts/lib/eval-json.sh"
failures=0
fail() { echo "interval-coverage: FAIL: $*"; failures=$((failures + 1)); }
listed() { grep -qx "$1" <(grep -v '^#' "$known" 2>/dev/null); }

row() {  # row NAME JSON: one table line
  local cells=""
  for p in mpe rpe mae rae; do
    cells="$cells | $(printf '%.1f' "$(value "$2" "$p" coverage_pct)") ($(printf '%.2f' "$(value "$2" "$p" mean_u95_um)"))"
  done
  echo "| $1 | $(top "$2" samples) | $(top "$2" outside_domain)$cells |"
}

echo "model $(sed -n 's/.*"checksum": "\(.\{16\}\).*/\1/p' "$model"), nominal coverage 95 %"
echo "| test set | moves | outside domain | coverage % (mean U95 µm) MPE | RPE | MAE | RAE |"
echo "|---|---|---|---|---|---|---|"
for seed in 2 4 5; do
  "$sim" dataset --design lhs --samples 270 --noise --seed "$seed" -o "$work/lhs$seed.csv" > /dev/null
  "$train" eval "$model" "$work/lhs$seed.csv" --json > "$work/lhs$seed.json"
  row "default twin, LHS 270 seed $seed" "$work/lhs$seed.json"
  if [ $check = 1 ]; then
    for p in mpe rpe mae rae; do
      c=$(value "$work/lhs$seed.json" "$p" coverage_pct)
      awk -v c="$c" 'BEGIN { exit !(c >= 92) }' || fail "seed $seed: $p coverage $c % < 92 %"
    done
  fi
done
# upper CHECK NAME COVERAGE: the upper end of the band, or the known-unmet list.
upper() {
  if listed "$2 over-covers"; then
    awk -v c="$3" 'BEGIN { exit !(c > 98) }' ||
      fail "$1: $2 coverage $3 % is within 92-98 %: remove '$2 over-covers' from $known"
  else
    awk -v c="$3" 'BEGIN { exit !(c <= 98) }' || fail "$1: $2 coverage $3 % > 98 %"
  fi
}
if [ $check = 1 ]; then
  for p in mpe rpe mae rae; do
    upper "seed 2" "$p" "$(value "$work/lhs2.json" "$p" coverage_pct)"
    pooled=$(for seed in 2 4 5; do value "$work/lhs$seed.json" "$p" coverage_pct; done |
      awk '{ s += $1 } END { print s / NR }')
    echo "pooled over seeds 2, 4, 5: $p coverage $(printf '%.1f' "$pooled") %"
    upper "pooled" "$p" "$pooled"
  done
fi
for name in variant-mode-20 variant-drag+30 variant-y-participation+30; do
  "$sim" dataset --design lhs --samples 270 --noise --seed 2 \
    --machine "$here/data/machines/$name.toml" -o "$work/$name.csv" > /dev/null
  "$train" eval "$model" "$work/$name.csv" --json > "$work/$name.json"
  row "unseen machine $name, LHS 270 seed 2" "$work/$name.json"
done
"$sim" dataset --design lhs --samples 270 --noise --seed 2 \
  --levels "pv=30,80,130;pd=40,60,80;av=8,12,16;ad=3,10,20" -o "$work/wide.csv" > /dev/null
"$train" eval "$model" "$work/wide.csv" --json > "$work/wide.json"
row "default twin, wider ranges (PV 30-130, AD 3-20)" "$work/wide.json"
# Corners: the 2^k corners of the training box less an edge margin m (each input at lo + m·w and
# hi - m·w), 10 noisy repeats each. The fit is worst in its corners, where the feed planner's
# optimum goes (docs/planner.md); the corner gain (model file version 3) widens U95 there.
corners() {  # corners MARGIN Y(0|1): --levels of the shrunk box's corners
  awk -v m="$1" -v y="$2" 'BEGIN {
    split("pv 40 100 pd 40 80 av 8 16 ad 5 15 y 0 500", t, " ");
    n = y ? 5 : 4; s = "";
    for (i = 0; i < n; ++i) {
      lo = t[3 * i + 2]; hi = t[3 * i + 3]; w = hi - lo;
      s = s (i ? ";" : "") t[3 * i + 1] "=" (lo + m * w) "," (hi - m * w);
    }
    print s }'
}
for margin in 0 0.1 0.2; do
  for which in 4 5; do
    if [ $which = 5 ]; then m="$here/data/models/default-y.json"; y=1; else m="$model"; y=0; fi
    "$sim" dataset --design full --repeats 10 --noise --seed 7 --levels "$(corners $margin $y)" \
      -o "$work/corners-$which-$margin.csv" > /dev/null
    "$train" eval "$m" "$work/corners-$which-$margin.csv" --json > "$work/corners-$which-$margin.json"
    row "$which-input model, corners of the box less margin $margin" "$work/corners-$which-$margin.json"
    if [ $check = 1 ] && [ "$margin" != 0.2 ]; then
      for p in mpe rpe mae rae; do
        c=$(value "$work/corners-$which-$margin.json" "$p" coverage_pct)
        awk -v c="$c" 'BEGIN { exit !(c >= 92) }' ||
          fail "$which-input model, corners less margin $margin: $p coverage $c % < 92 %"
      done
    fi
  done
done
if [ $check = 1 ]; then
  outside=$(top "$work/wide.json" outside_domain)
  [ "$outside" -gt 0 ] || fail "no move of the wider set was flagged outside the domain"
  grows=0
  for p in mpe rpe mae rae; do
    wide=$(value "$work/wide.json" "$p" mean_u95_um)
    inside=$(value "$work/lhs2.json" "$p" mean_u95_um)
    awk -v w="$wide" -v i="$inside" 'BEGIN { exit !(w > i) }' && grows=1
    c=$(value "$work/wide.json" "$p" coverage_pct)
    awk -v c="$c" 'BEGIN { exit !(c >= 92) }' || fail "wider ranges: $p coverage $c % < 92 %"
  done
  [ $grows = 1 ] || fail "wider ranges: no parameter's mean U95 grew outside the domain"
  [ $failures = 0 ] || exit 1
  echo "interval-coverage: PASS"
fi
