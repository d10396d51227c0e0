# SPDX-License-Identifier: MIT
# Sourced by scripts that read `cmmcomp-train eval --json` (no jq on a fresh machine).
# value FILE PARAMETER KEY: one number of parameter PARAMETER (mpe, rpe, mae, rae).
value() {
  awk -v want="$2" -v field="$3" '/^  "(mpe|rpe|mae|rae)"/ { gsub(/[":{ ]/, ""); key = $0 }
       key == want && $0 ~ "\"" field "\"" { gsub(/[",]/, ""); print $2 }' "$1"
}
# top FILE KEY: a top-level number (samples, outside_domain, interval_coverage_nominal_pct).
top() {
  awk -v field="$2" '$0 ~ "^  \"" field "\"" { gsub(/[",]/, ""); print $2 }' "$1"
}
