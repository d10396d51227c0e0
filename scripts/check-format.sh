#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# Fails when a C/C++ file of the checkout (tracked, or new and not ignored) is not clang-formatted.
# Pass --fix to format them all in place.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
# Tracked files and new ones not yet added (so --fix before `git add` covers them too).
mapfile -t files < <(git ls-files --cached --others --exclude-standard \
  '*.hpp' '*.cpp' '*.h' '*.c' 2>/dev/null || true)
# No git (e.g. an unpacked source archive): every C/C++ file under the source directories.
if [ ${#files[@]} -eq 0 ]; then
  mapfile -t files < <(find include src tools tests bench plugins examples -type f \
    \( -name '*.hpp' -o -name '*.cpp' -o -name '*.h' -o -name '*.c' \) 2>/dev/null)
fi
if [ "${1:-}" = "--fix" ]; then
  clang-format -i "${files[@]}"
  exit 0
fi
bad=0
for f in "${files[@]}"; do
  if ! clang-format --dry-run --Werror "$f" >/dev/null 2>&1; then
    echo "not clang-formatted: $f (run: bash scripts/check-format.sh --fix)"
    bad=1
  fi
done
[ $bad -eq 0 ] && echo "format check: ${#files[@]} files clean"
exit $bad
