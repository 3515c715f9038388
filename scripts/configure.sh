#!/usr/bin/env bash
# configure.sh BUILD_DIR CMAKE_ARGS...: runs cmake for BUILD_DIR only when it has not
# been configured yet or was configured with other arguments, so `make test` on an
# unchanged tree goes straight to the build (which re-runs cmake itself when a
# CMakeLists.txt changed).
set -euo pipefail
build=$1
shift
wanted="$*"
stamp="$build/.rangekit-configure-args"
if [ -f "$build/CMakeCache.txt" ] && [ -f "$stamp" ] && [ "$(cat "$stamp")" = "$wanted" ]; then
  exit 0
fi
cmake -S . -B "$build" "$@" >/dev/null
printf '%s' "$wanted" >"$stamp"
