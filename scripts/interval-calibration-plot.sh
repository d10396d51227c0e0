#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# The calibration plot of the prediction interval (docs/uncertainty.md, "Calibration plot"):
# nominal against empirical coverage from 50 to 99 %. For each nominal coverage c the shipped
# recipe (scripts/train-default-model.sh: L18 x 3 seed 1 + LHS 270 seed 3 of the default twin,
# Table 1 noise) is trained with `cmmcomp-train fit --interval-coverage c`, and the share of
# held-out moves (LHS 270, seeds 2, 4 and 5: 810 moves) whose measured value lies within
# predicted +- U_c is measured with `cmmcomp-train eval --json`.
# Writes OUT/interval-calibration.csv and OUT/interval-calibration.png (gnuplot) and prints the
# table: a measurement, not a check (the 95 % level is checked by cmmcomp-study interval-coverage).
# Usage: bash scripts/interval-calibration-plot.sh [OUT]   (needs the release tools; about 6 min)
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bin="${CMMCOMP_BIN:-$here/build/release/tools}"
sim="$bin/cmmcomp-sim/cmmcomp-sim"
train="$bin/cmmcomp-train/cmmcomp-train"
# shellcheck source=lib/tool-script.sh
source "$here/scripts/lib/tool-script.sh"
require_tools interval-calibration-plot "$sim" "$train"
parse_check_and_work "${1:-}"
# shellcheck source=lib/eval-json.sh
source "$here/scripts/lib/eval-json.sh"
command -v gnuplot > /dev/null || { echo "interval-calibration-plot: gnuplot is missing" >&2; exit 2; }

"$sim" dataset --design l18 --repeats 3 --noise --seed 1 -o "$work/l18x3.csv" > /dev/null
"$sim" dataset --design lhs --samples 270 --noise --seed 3 -o "$work/lhs270.csv" > /dev/null
{ cat "$work/l18x3.csv"; tail -n +2 "$work/lhs270.csv"; } > "$work/train.csv"
"$sim" dataset --design lhs --samples 270 --noise --seed 2 -o "$work/test2.csv" > /dev/null
for seed in 4 5; do
  "$sim" dataset --design lhs --samples 270 --noise --seed "$seed" -o "$work/t$seed.csv" > /dev/null
done
{ cat "$work/test2.csv"; tail -n +2 "$work/t4.csv"; tail -n +2 "$work/t5.csv"; } > "$work/test.csv"

csv="$work/interval-calibration.csv"
echo "nominal_pct,mpe_pct,rpe_pct,mae_pct,rae_pct" > "$csv"
echo "| nominal % | MPE | RPE | MAE | RAE | (empirical coverage % on 810 held-out moves)"
echo "|---|---|---|---|---|"
for c in 0.50 0.60 0.70 0.80 0.90 0.95 0.99; do
  "$train" fit "$work/train.csv" --seed 1 --interval-coverage "$c" -o "$work/model-$c.json" > /dev/null
  "$train" eval "$work/model-$c.json" "$work/test.csv" --json > "$work/eval-$c.json"
  nominal=$(awk -v c="$c" 'BEGIN { printf "%g", 100 * c }')
  row="$nominal"
  for p in mpe rpe mae rae; do
    got=$(value "$work/eval-$c.json" "$p" coverage_pct)
    row="$row,$got"
  done
  echo "$row" >> "$csv"
  echo "$row" | awk -F, '{ printf "| %s | %.1f | %.1f | %.1f | %.1f |\n", $1, $2, $3, $4, $5 }'
done

png="$work/interval-calibration.png"
gnuplot <<GNUPLOT
set terminal pngcairo size 900,700 noenhanced
set output '$png'
set datafile separator ','
set title 'Prediction interval: nominal vs empirical coverage (810 held-out twin moves)'
set xlabel 'nominal coverage %'
set ylabel 'empirical coverage %'
set xrange [45:100]
set yrange [45:100]
set key bottom right
set grid
plot x title 'ideal' with lines lc rgb '#888888' dt 2, \
  '$csv' using 1:2 skip 1 title 'MPE' with linespoints pt 7, \
  '$csv' using 1:3 skip 1 title 'RPE' with linespoints pt 5, \
  '$csv' using 1:4 skip 1 title 'MAE' with linespoints pt 9, \
  '$csv' using 1:5 skip 1 title 'RAE' with linespoints pt 11
GNUPLOT
echo "wrote $csv and $png"
