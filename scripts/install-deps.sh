#!/usr/bin/env bash
# SPDX-License-Identifier: MIT
# install-deps.sh [main|test]: installs, from Debian's packages only, what this machine lacks for
# README command 1 (`main`: build the tools and run the main job; the default) or command 2
# (`test`: main's, plus the test toolchain: UML and CAN utilities, Modbus clients, the firmware
# and aarch64 cross compilers and QEMU, clang for the sanitizers, clang-format, clang-tidy). Idempotent: a
# second run installs nothing. Needs root (or sudo) only when something is missing.
set -euo pipefail
what="${1:-main}"

main=(
  build-essential cmake ninja-build pkg-config
  libeigen3-dev libsundials-dev libceres-dev libmodbus-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libcli11-dev libfmt-dev libspdlog-dev nlohmann-json3-dev libtomlplusplus-dev
  gnuplot-nox
)
test=(
  can-utils user-mode-linux kmod iproute2 mbpoll socat
  clang-format clang-tidy systemd dpkg-dev file python3
  gcc-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib qemu-system-arm
  g++-aarch64-linux-gnu qemu-user
  clang libclang-rt-14-dev libomp-14-dev
)
case "$what" in
  main) packages=("${main[@]}") ;;
  test) packages=("${main[@]}" "${test[@]}") ;;
  *) echo "install-deps: '$what' is neither main nor test" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages for '$what' present"
  exit 0
fi

echo "install-deps: installing ${missing[*]}"
sudo_cmd=()
if [ "$(id -u)" -ne 0 ]; then sudo_cmd=(sudo); fi
export DEBIAN_FRONTEND=noninteractive
"${sudo_cmd[@]}" apt-get update -qq
"${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
