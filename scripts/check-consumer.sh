#!/usr/bin/env bash
# Builds tests/consumer against rangekit three ways and runs it each time:
#   1. the package installed by `cmake --install` into a temporary prefix (find_package),
#   2. the same prefix through pkg-config,
#   3. the source tree as a subproject (add_subdirectory).
# Usage: scripts/check-consumer.sh BUILD_DIR
set -euo pipefail
build=${1:?usage: check-consumer.sh BUILD_DIR}
root=$(cd "$(dirname "$0")/.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
jobs=$(nproc 2>/dev/null || echo 2)

# What the consumer must print: typed from ULS §8 and LS5 §9.4, not from rangekit.
expected="uls 12.345 m 33000 ps
ls5 address 2 parameter 0B value 01"

check_output() {
  local how=$1 binary=$2
  local output
  if ! output=$("$binary" 2>&1); then
    printf 'consumer (%s) failed:\n%s\n' "$how" "$output" >&2
    exit 1
  fi
  if [ "$(printf '%s\n' "$output" | tail -n 2)" != "$expected" ]; then
    printf 'consumer (%s) printed:\n%s\nexpected:\n%s\n' "$how" "$output" "$expected" >&2
    exit 1
  fi
  echo "consumer ($how): ok"
}

cmake --install "$build" --prefix "$work/prefix" >/dev/null
test -f "$work/prefix/include/rangekit/version.hpp"
# rangekit::sim's headers: the runtime's and, beside each family's codec, its firmware model's.
test -f "$work/prefix/include/rangekit/sim/emulator_runtime.hpp"
test -f "$work/prefix/include/rangekit/uls/emulator/firmware.hpp"
test -f "$work/prefix/include/rangekit/ls5/emulator/firmware.hpp"

cmake -S "$root/tests/consumer" -B "$work/installed" -DCMAKE_PREFIX_PATH="$work/prefix" >/dev/null
cmake --build "$work/installed" -j"$jobs" >/dev/null
check_output "find_package" "$work/installed/consumer"

pc_dir=$(dirname "$(find "$work/prefix" -name rangekit.pc)")
# shellcheck disable=SC2046 # the flags are words
c++ -o "$work/pkg-config-consumer" "$root/tests/consumer/main.cpp" \
  $(PKG_CONFIG_PATH="$pc_dir" pkg-config --cflags --libs rangekit)
check_output "pkg-config" "$work/pkg-config-consumer"

cmake -S "$root/tests/consumer" -B "$work/subproject" -DRANGEKIT_SOURCE="$root" >/dev/null
# Only what the consumer links (its libraries and theirs), as a user's build of their own target would.
cmake --build "$work/subproject" -j"$jobs" --target consumer >/dev/null
# As a subproject rangekit builds its libraries only: no tests, CLI or benchmarks.
if [ -e "$work/subproject/rangekit/rangekit" ] || ls "$work/subproject/rangekit/"*_tests >/dev/null 2>&1; then
  echo "consumer (add_subdirectory): rangekit built its CLI or tests as a subproject" >&2
  exit 1
fi
check_output "add_subdirectory" "$work/subproject/consumer"
