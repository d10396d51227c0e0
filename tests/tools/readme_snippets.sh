#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest docs_readme_snippets: every ```cpp or ```c block of docs/library.md's "Library" section is an
# excerpt of one program in examples/: its lines (leading blanks ignored) occur in that file in
# the same order. So the page shows code that CI builds and runs (consumer_find_package).
# Usage: readme_snippets.sh docs/library.md EXAMPLES_DIR
set -euo pipefail
readme=$1 examples=$2
section=$(awk '/^## Library/{on=1; next} /^## /{on=0} on' "$readme")
[ -n "$section" ] || { echo "readme_snippets: FAIL: no '## Library' section in $readme"; exit 1; }
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# Split the section's C and C++ blocks into work/block-N.
awk -v dir="$work" '
  /^```(cpp|c)$/ { n++; on = 1; next }
  /^```/ { on = 0; next }
  on { sub(/^[ \t]+/, ""); if (length($0) > 0) print > (dir "/block-" n) }
' <<< "$section"
blocks=("$work"/block-*)
[ -e "${blocks[0]}" ] || { echo "readme_snippets: FAIL: no code blocks"; exit 1; }
failed=0
for block in "${blocks[@]}"; do
  found=""
  for example in "$examples"/[0-9][0-9]_*.c "$examples"/[0-9][0-9]_*.cpp; do
    # Ordered subsequence: each block line matches a later example line exactly.
    if awk 'NR == FNR { want[++n] = $0; next }
            { sub(/^[ \t]+/, ""); if (k < n && $0 == want[k + 1]) ++k }
            END { exit(k == n ? 0 : 1) }' "$block" "$example"; then
      found=$example
      break
    fi
  done
  if [ -n "$found" ]; then
    echo "readme_snippets: $(basename "$block"): $(basename "$found")"
  else
    echo "readme_snippets: FAIL: this block of the page is in no example:"
    cat "$block"
    failed=1
  fi
done
[ "$failed" -eq 0 ] && echo "readme_snippets: PASS (${#blocks[@]} blocks)"
exit "$failed"
