#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest accuracy_l18_cell_interpolant: what the paper's L18 x 3 data hold about RPE
# (docs/training.md, "Why RPE's residual misses"). RPE depends on PV and PD only, and any two
# three-level columns of the L18 hold all nine (PV, PD) cells, six samples each. The tensor quadratic through
# the nine cell means (Lagrange in PV times Lagrange in PD) is the plain interpolant of those
# data. Tested on LHS 270 with Table 1 noise, as the accuracy ctests test the network, it must:
#  - meet the paper's RPE reduction (90.8 %): the data carry it, so a network trained on them that
#    misses it (accuracy_fnn_default_twin, accuracy_cross_machine) loses it between the levels;
#  - miss the residual limit 1.5 x the noise floor (0.555 um): three levels of PV and PD do not
#    carry RPE's bend along the triangular boundary finely enough for it.
# Cases: the default machine, train seed 1 -> test seeds 2, 4, 5, and 11 -> 12, 21 -> 22 (the seed
# pairs of accuracy_fnn_default_twin); each variant machine 1 -> 2 (the datasets straight from
# the twin, not through recordings as accuracy_cross_machine runs them).
# Usage: l18_cell_interpolant.sh TOOLS_DIR MACHINES_DIR WORK_DIR
set -euo pipefail
bin=$(cd "$1" && pwd) machines=$(cd "$2" && pwd) work=$3
sim=$bin/cmmcomp-sim/cmmcomp-sim
rm -rf "$work" && mkdir -p "$work" && cd "$work"

paper_reduction=90.8 limit=0.555 failures=0

# interpolant TRAIN.csv TEST.csv: prints "before after reduction" (um, um, %) of RPE.
interpolant() {
  awk -F, '
    FNR == 1 { for (c = 1; c <= NF; ++c) col[$c] = c; next }
    FILENAME == ARGV[1] {
      pv = $col["pv_mm_s"] + 0; pd = $col["pd_mm"] + 0
      sum[pv, pd] += $col["rpe_um"]; cnt[pv, pd]++; pvs[pv]; pds[pd]; next
    }
    { test_pv[++n] = $col["pv_mm_s"] + 0; test_pd[n] = $col["pd_mm"] + 0; test_rpe[n] = $col["rpe_um"] + 0 }
    function levels(set, out,   k, m, i, j, t) {
      m = 0; for (k in set) out[++m] = k + 0
      for (i = 1; i <= m; ++i) for (j = i + 1; j <= m; ++j) if (out[j] < out[i]) { t = out[i]; out[i] = out[j]; out[j] = t }
      return m
    }
    function lagrange(x, lv, i,   j, w) {
      w = 1; for (j = 1; j <= 3; ++j) if (j != i) w *= (x - lv[j]) / (lv[i] - lv[j])
      return w
    }
    END {
      if (levels(pvs, lpv) != 3 || levels(pds, lpd) != 3) { print "not three PV and PD levels"; exit 2 }
      for (i = 1; i <= 3; ++i) for (j = 1; j <= 3; ++j) {
        if (!cnt[lpv[i], lpd[j]]) { print "cell PV " lpv[i] " PD " lpd[j] " is empty"; exit 2 }
        cell[i, j] = sum[lpv[i], lpd[j]] / cnt[lpv[i], lpd[j]]
      }
      for (k = 1; k <= n; ++k) {
        p = 0
        for (i = 1; i <= 3; ++i) for (j = 1; j <= 3; ++j)
          p += lagrange(test_pv[k], lpv, i) * lagrange(test_pd[k], lpd, j) * cell[i, j]
        before += (test_rpe[k] < 0 ? -test_rpe[k] : test_rpe[k])
        r = test_rpe[k] - p; after += (r < 0 ? -r : r)
      }
      printf "%.3f %.3f %.1f\n", before / n, after / n, 100 * (1 - after / before)
    }' "$1" "$2"
}

check() {  # check NAME MACHINE TRAIN_SEED TEST_SEED
  local name=$1 machine=$2 tr=$3 te=$4
  "$sim" dataset --design l18 --repeats 3 --noise --seed "$tr" --machine "$machine" \
    -o "$name-l18x3-$tr.csv" > /dev/null
  "$sim" dataset --design lhs --samples 270 --noise --seed "$te" --machine "$machine" \
    -o "$name-lhs270-$te.csv" > /dev/null
  read -r before after reduction < <(interpolant "$name-l18x3-$tr.csv" "$name-lhs270-$te.csv")
  echo "$name L18x3 seed $tr -> LHS270 seed $te: RPE mean before $before um," \
    "cell interpolant mean |residual| $after um, reduction $reduction %"
  if ! awk -v r="$reduction" -v p="$paper_reduction" 'BEGIN { exit !(r >= p) }'; then
    echo "FAIL: $name $tr -> $te: the cell interpolant's reduction $reduction % < $paper_reduction %"
    failures=$((failures + 1))
  fi
  if ! awk -v a="$after" -v l="$limit" 'BEGIN { exit !(a > l) }'; then
    echo "FAIL: $name $tr -> $te: the cell interpolant's residual $after um now meets $limit um:" \
      "docs/training.md (why RPE's residual misses) is out of date"
    failures=$((failures + 1))
  fi
}

for te in 2 4 5; do check default "$machines/default.toml" 1 "$te"; done
check default "$machines/default.toml" 11 12  # the other seed pairs of accuracy_fnn_default_twin
check default "$machines/default.toml" 21 22
for variant in mode-20 drag+30 y-participation+30; do
  check "$variant" "$machines/variant-$variant.toml" 1 2
done
[ "$failures" = 0 ] || { echo "accuracy_l18_cell_interpolant: $failures failed"; exit 1; }
echo "accuracy_l18_cell_interpolant: PASS"
