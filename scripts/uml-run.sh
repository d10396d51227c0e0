#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# uml-run.sh [--timeout S] [--mem SIZE] -- COMMAND ARGS...
#
# Runs COMMAND inside a User-Mode Linux guest that has real SocketCAN: the Debian UML kernel
# (package user-mode-linux) boots with the host's / as its root file system (hostfs), loads the
# can, can-raw, can-bcm, can-dev and vcan modules, brings up vcan0 (classic CAN, MTU 16) and
# vcan1 (CAN FD capable, MTU 72; classic frames work there too), changes to the
# caller's working directory, runs COMMAND as root inside the guest with the caller's
# environment, and powers off. COMMAND's stdout and stderr are copied to ours after the guest
# stops, and its exit status becomes ours (UML itself always exits 0, so the guest writes $? to a
# file in a host temporary directory).
#
# Exit status: COMMAND's; 124 when the guest did not finish within --timeout seconds (UML's
# whole process group is killed); 125 when the guest could not be started or ended without
# running COMMAND to its end; 1 when linux.uml or its modules are missing (never 77: a missing
# environment is a failure in CI, scripts/install-deps.sh installs it).
# Why a guest: the development and CI kernels have no AF_CAN (shared/SOCKETCAN.md, beside the
# repository).
set -euo pipefail

timeout_s=120
mem=256M
while [ $# -gt 0 ]; do
  case "$1" in
    --timeout) timeout_s="$2"; shift 2 ;;
    --mem) mem="$2"; shift 2 ;;
    --) shift; break ;;
    -h|--help)
      sed -n '3,19p' "${BASH_SOURCE[0]}" | sed 's/^# \{0,1\}//'
      exit 0 ;;
    *) echo "uml-run: unknown option '$1' (usage: uml-run.sh [--timeout S] -- COMMAND ARGS...)" >&2
       exit 2 ;;
  esac
done
if [ $# -eq 0 ]; then
  echo "uml-run: no command (usage: uml-run.sh [--timeout S] -- COMMAND ARGS...)" >&2
  exit 2
fi

uml="$(command -v linux.uml || true)"
if [ -z "$uml" ]; then
  echo "uml-run: linux.uml not found: install the Debian package user-mode-linux" \
       "(bash scripts/install-deps.sh does)" >&2
  exit 1
fi
version="$("$uml" --version)"
modules="/usr/lib/uml/modules/$version"
if [ ! -f "$modules/modules.dep" ]; then
  echo "uml-run: no UML modules in $modules (package user-mode-linux incomplete?)" >&2
  exit 1
fi
for tool in modprobe ip; do
  for dir in /usr/sbin /sbin /usr/bin /bin; do [ -x "$dir/$tool" ] && continue 2; done
  echo "uml-run: '$tool' not found: install kmod and iproute2" >&2
  exit 1
done

# The guest sees the host's /, so everything it needs lives in one host temporary directory.
# /tmp rather than /dev/shm: UML puts the guest's memory in /dev/shm (TMPDIR) already.
work="$(mktemp -d "${TMPDIR:-/tmp}/uml-run.XXXXXX")"
uml_pid=""
cleanup() {
  if [ -n "$uml_pid" ] && kill -0 "$uml_pid" 2>/dev/null; then
    kill -KILL -- "-$uml_pid" 2>/dev/null || kill -KILL "$uml_pid" 2>/dev/null || true
    wait "$uml_pid" 2>/dev/null || true
  fi
  rm -rf "$work"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# modprobe -d TREE looks in TREE/lib/modules/<version>; a symlink there avoids creating
# /lib/modules/<version> on the host (the host's own kernel modules live there).
mkdir -p "$work/tree/lib/modules" "$work/uml"
ln -s "$modules" "$work/tree/lib/modules/$version"

# The caller's environment (bash-quoted), its working directory and the command, for init.
export -p | grep -v -E '^declare -x (PWD|OLDPWD|SHLVL|_)=' >"$work/env.sh" || true
printf '%q ' "$@" >"$work/command"

cat >"$work/init.sh" <<EOF
#!/bin/bash
# PID 1 of the guest. Must never exit: that panics the guest kernel; it powers off instead.
export PATH=/usr/sbin:/usr/bin:/sbin:/bin
power_off() { sync; echo o >/proc/sysrq-trigger; sleep 10; }
mount -t proc proc /proc
mount -t sysfs sysfs /sys
mount -t tmpfs tmpfs /run 2>/dev/null || true
if ! modprobe -d '$work/tree' -a can can-raw can-bcm can-dev vcan 2>'$work/setup.err' ||
   ! { ip link add dev vcan0 type vcan && ip link set vcan0 mtu 16 && ip link set up vcan0 &&
       ip link add dev vcan1 type vcan && ip link set vcan1 mtu 72 && ip link set up vcan1 &&
       ip link set up lo; } \
       2>>'$work/setup.err'; then
  echo setup-failed >'$work/rc'
  power_off
fi
. '$work/env.sh'
export PATH="\$PATH:/usr/sbin:/sbin"
cd '$PWD' || { echo cd-failed >'$work/rc'; power_off; }
( $(cat "$work/command") ) </dev/null >'$work/stdout' 2>'$work/stderr'
echo \$? >'$work/rc.tmp' && mv '$work/rc.tmp' '$work/rc'
power_off
EOF
chmod +x "$work/init.sh"

# initcall_blacklist skips ≈ 0.85 s of RAID benchmarks; quiet keeps the console silent.
"$uml" mem="$mem" root=/dev/root rootfstype=hostfs hostfs=/ rw init="$work/init.sh" \
  initcall_blacklist=raid6_select_algo,calibrate_xor_blocks quiet loglevel=0 \
  uml_dir="$work/uml" umid=guest con=null con0=null,fd:2 ssl=null \
  </dev/null >"$work/console" 2>&1 &
uml_pid=$!

deadline_ms=$(( $(date +%s%3N) + timeout_s * 1000 ))
status=""
while kill -0 "$uml_pid" 2>/dev/null; do
  if [ "$(date +%s%3N)" -ge "$deadline_ms" ]; then
    # UML calls setsid(): its helper processes are in the group led by its main process.
    pgid="$(cat "$work/uml/guest/pid" 2>/dev/null || echo "$uml_pid")"
    kill -KILL -- "-$pgid" 2>/dev/null || true
    kill -KILL -- "-$uml_pid" 2>/dev/null || kill -KILL "$uml_pid" 2>/dev/null || true
    status=124
    break
  fi
  sleep 0.05
done
wait "$uml_pid" 2>/dev/null || true
uml_pid=""

[ -f "$work/stdout" ] && cat "$work/stdout"
[ -f "$work/stderr" ] && cat "$work/stderr" >&2
if [ "$status" = 124 ]; then
  echo "uml-run: timed out after ${timeout_s} s; guest killed" >&2
  exit 124
fi
rc="$(cat "$work/rc" 2>/dev/null || true)"
case "$rc" in
  ''|*[!0-9]*)
    echo "uml-run: the guest did not run the command to its end (${rc:-no status})" >&2
    [ -s "$work/setup.err" ] && sed 's/^/uml-run: setup: /' "$work/setup.err" >&2
    tail -n 20 "$work/console" | sed 's/^/uml-run: console: /' >&2
    exit 125 ;;
esac
exit "$rc"
