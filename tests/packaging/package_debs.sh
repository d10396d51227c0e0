#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# ctest package_debs (docs/agent.md, "Packages"): builds the Debian packages of BUILD_DIR with
# CPack, extracts each into a scratch root with dpkg -x, checks what they hold, verifies the
# systemd unit, and runs the installed programs from the scratch root.
# Usage: package_debs.sh BUILD_DIR WORK_DIR SOURCE_DIR
set -euo pipefail
build=$1 work=$2 source=$3
rm -rf "$work"
mkdir -p "$work/debs" "$work/root"
fail() { echo "package_debs: FAIL: $*" >&2; exit 1; }

(cd "$build" && cpack -G DEB -B "$work/debs" > "$work/cpack.log") || { cat "$work/cpack.log"; fail "cpack"; }
for p in cmmcomp-dev cmmcomp-tools cmmcomp-agent; do
  deb=$(ls "$work/debs/${p}_"*.deb 2>/dev/null) || fail "no $p package"
  info=$(dpkg-deb --info "$deb")
  grep -q "Package: $p" <<< "$info" || fail "$deb is not $p"
  dpkg -x "$deb" "$work/root"
  echo "package_debs: $p: $(sed -n 's/^ Depends: //p' <<< "$info")"
done
root=$work/root

# What each package must hold.
for f in usr/include/cmmcomp/schema.hpp usr/include/cmmcomp/compensator.h \
         usr/lib/cmake/cmmcomp/cmmcompConfig.cmake usr/lib/pkgconfig/cmmcomp-core.pc \
         usr/lib/pkgconfig/cmmcomp-capi.pc usr/share/cmmcomp/models/default.json \
         usr/bin/cmmcomp-sim usr/bin/cmmcomp-train usr/bin/cmmcomp-measure usr/bin/cmmcomp-replay \
         usr/bin/cmmcomp-vc \
         usr/bin/cmmcomp-agent usr/lib/systemd/system/cmmcomp-agent.service \
         usr/lib/systemd/system/cmmcomp-ipp-proxy.service etc/cmmcomp/ipp-proxy.env \
         usr/share/doc/cmmcomp-agent/protocol-ippdme.md \
         etc/cmmcomp/agent.toml; do
  [ -e "$root/$f" ] || fail "missing /$f"
done
ls "$root"/usr/lib/libcmmcomp_capi.so.* > /dev/null || fail "missing libcmmcomp_capi.so"
dpkg-deb -e "$(ls "$work"/debs/cmmcomp-agent_*.deb)" "$work/control"
grep -qx /etc/cmmcomp/agent.toml "$work/control/conffiles" || fail "agent.toml is not a conffile"
grep -qx /etc/cmmcomp/ipp-proxy.env "$work/control/conffiles" || fail "ipp-proxy.env is not a conffile"

# The unit, against this machine's systemd units; its ExecStart, /usr/bin/cmmcomp-agent, is
# pointed at the scratch root's copy (verify checks that the program exists and is executable).
if command -v systemd-analyze > /dev/null; then
  sed "s|/usr/bin/cmmcomp-agent|$root/usr/bin/cmmcomp-agent|" \
    "$root/usr/lib/systemd/system/cmmcomp-agent.service" > "$work/cmmcomp-agent.service"
  grep -q "^ExecStart=$root/usr/bin/cmmcomp-agent --config" "$work/cmmcomp-agent.service" \
    || fail "the unit's ExecStart is not the packaged agent"
  systemd-analyze verify "$work/cmmcomp-agent.service" > "$work/verify.log" 2>&1 \
    || { cat "$work/verify.log"; fail "systemd-analyze verify"; }
  if [ -s "$work/verify.log" ]; then cat "$work/verify.log"; fail "systemd-analyze verify warned"; fi
  # The I++ proxy's unit reads its command line from /etc/cmmcomp/ipp-proxy.env.
  sed -e "s|/usr/bin/cmmcomp-agent|$root/usr/bin/cmmcomp-agent|" \
      -e "s|^EnvironmentFile=/etc/cmmcomp/|EnvironmentFile=$root/etc/cmmcomp/|" \
    "$root/usr/lib/systemd/system/cmmcomp-ipp-proxy.service" > "$work/cmmcomp-ipp-proxy.service"
  systemd-analyze verify "$work/cmmcomp-ipp-proxy.service" > "$work/verify.log" 2>&1 \
    || { cat "$work/verify.log"; fail "systemd-analyze verify (ipp proxy)"; }
  if [ -s "$work/verify.log" ]; then cat "$work/verify.log"; fail "systemd-analyze verify warned"; fi
  echo "package_debs: systemd-analyze verify: ok"
else
  fail "systemd-analyze not found (install-deps installs systemd)"
fi

# The installed programs, run from the scratch root.
# Outputs are captured first, then matched: grep -q on a pipe would SIGPIPE the writer.
out=$("$root/usr/bin/cmmcomp-agent" --version) || fail "agent --version"
grep -q "cmmcomp-agent" <<< "$out" || fail "agent --version: $out"
out=$("$root/usr/bin/cmmcomp-agent" --config "$root/etc/cmmcomp/agent.toml" --check 2>&1) \
  || fail "agent --check of the installed config: $out"
grep -q "settings and 1 model(s) are valid" <<< "$out" || fail "agent --check: $out"
# The proxy's shipped command line, checked as the unit runs it (--check: models, no serving).
set -a; . "$root/etc/cmmcomp/ipp-proxy.env"; set +a
# shellcheck disable=SC2086  # the variable is the unit's word-split command line
out=$("$root/usr/bin/cmmcomp-agent" $CMMCOMP_IPP_PROXY_ARGS --check 2>&1) \
  || fail "agent with ipp-proxy.env --check: $out"
grep -q "settings and 1 model(s) are valid" <<< "$out" || fail "ipp proxy --check: $out"
out=$("$root/usr/bin/cmmcomp-sim" move --json) || fail "cmmcomp-sim move"
grep -q '"rae_um"' <<< "$out" || fail "cmmcomp-sim move: $out"
"$root/usr/bin/cmmcomp-train" export "$root/usr/share/cmmcomp/models/default.json" \
  --header "$work/model.hpp" > /dev/null || fail "cmmcomp-train export"
"$root/usr/bin/cmmcomp-measure" plan --repeats 1 -o "$work/plan" > /dev/null \
  || fail "cmmcomp-measure plan"
grep -q ' PtMeas(' "$work/plan/plan.ipp" || fail "cmmcomp-measure plan: no I++ program"
"$root/usr/bin/cmmcomp-replay" --help > /dev/null || fail "cmmcomp-replay --help"
"$root/usr/bin/cmmcomp-vc" --help > /dev/null || fail "cmmcomp-vc --help"

# A C program built with the installed headers and pkg-config file, on the installed library.
flags=$(PKG_CONFIG_PATH="$root/usr/lib/pkgconfig" pkg-config --cflags --libs cmmcomp-capi)
cc -std=c99 -Wall -Werror -o "$work/capi_from_package" "$source/tests/packaging/capi_from_package.c" \
  $flags -lm || fail "compile against the package"
LD_LIBRARY_PATH="$root/usr/lib" "$work/capi_from_package" "$root/usr/share/cmmcomp/models/default.json" \
  || fail "the C ABI from the package"
echo "package_debs: PASS"
