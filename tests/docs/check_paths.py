#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""ctest docs_paths_exist: every repository path a document or a code comment names exists.

Scans the tracked Markdown files and C/C++ sources and headers for paths that start with one of
the repository's top folders (src/, include/, tools/, docs/, scripts/, tests/, data/, plugins/,
examples/, bench/, fuzz/, cmake/, packaging/) and reports each that names no file or folder, with
the file and line. A path with a placeholder (<…>, *, …, {…}, $) is a pattern, not a path.
Usage: check_paths.py SOURCE_DIR
"""
import os
import re
import subprocess
import sys

TOPS = ("src", "include", "tools", "docs", "scripts", "tests", "data", "plugins", "examples",
        "bench", "fuzz", "cmake", "packaging")
PATH = re.compile(r"(?<![\w./-])((?:%s)/[A-Za-z0-9_.+/<>*{}$…-]*[A-Za-z0-9_+/>*}-])" % "|".join(TOPS))


def exists(root: str, name: str, path: str) -> bool:
    """True when `path`, as `name` (a file of the repository) names it, is a file or folder: from
    the repository's top, from `name`'s folder or one above it (a plugin's README names its own
    src/), as a header under any include/cmmcomp/, or as a target built from a source (a bench or
    a test named without its .cpp)."""
    folder = os.path.dirname(name)
    bases = [root]
    while folder:
        bases.append(os.path.join(root, folder))
        folder = os.path.dirname(folder)
    for base in bases:
        candidate = os.path.join(base, path)
        if os.path.exists(candidate):
            return True
        if any(os.path.exists(candidate + ext) for ext in (".cpp", ".hpp", ".c", ".h", ".sh")):
            return True
    for include in ("include/cmmcomp", "plugins/can/include/cmmcomp", "plugins/modbus/include/cmmcomp"):
        if os.path.exists(os.path.join(root, include, path)):
            return True
    if path.startswith("include/cmmcomp/plugins"):
        rest = path[len("include/cmmcomp/plugins"):]
        return any(os.path.exists(os.path.join(root, "plugins", p, "include/cmmcomp/plugins" + rest))
                   for p in ("can", "modbus"))
    return False


def main() -> int:
    root = sys.argv[1]
    files = subprocess.run(["git", "-C", root, "ls-files"], check=True, capture_output=True,
                           text=True).stdout.split()
    scanned = [f for f in files if f.endswith((".md", ".hpp", ".h", ".cpp", ".c"))
               and not f.startswith("data/models/")]
    missing = []
    checked = 0
    for name in scanned:
        with open(os.path.join(root, name), encoding="utf-8", errors="replace") as f:
            for number, line in enumerate(f, 1):
                for match in PATH.finditer(line):
                    path = match.group(1).rstrip("/.")
                    if any(c in path for c in "<>*{}$…"):
                        continue
                    # A name that continues a longer path in prose ("tests/tools/…") is cut at the
                    # last component that exists or at the whole path.
                    if line.lstrip().startswith("#include"):
                        continue  # the compiler checks those
                    checked += 1
                    if not exists(root, name, path):
                        missing.append(f"{name}:{number}: {path}")
    for m in missing:
        print(f"docs_paths_exist: no such path: {m}")
    print(f"docs_paths_exist: {'FAIL' if missing else 'PASS'} ({checked} paths in "
          f"{len(scanned)} files, {len(missing)} missing)")
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main())
