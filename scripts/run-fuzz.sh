#!/usr/bin/env bash
# Runs every libFuzzer binary in DIR for SECONDS each, starting from its seed
# corpus in fuzz/corpus/<name>/ (never modified: new inputs go to a work copy).
set -euo pipefail
dir=${1:?usage: run-fuzz.sh FUZZER_DIR SECONDS}
seconds=${2:-30}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for fuzzer in "$dir"/*; do
  [ -x "$fuzzer" ] || continue
  name=$(basename "$fuzzer")
  mkdir -p "$work/$name"
  seeds="fuzz/corpus/$name"
  [ -d "$seeds" ] || seeds=""
  echo "== $name ($seconds s)"
  if ! "$fuzzer" -max_total_time="$seconds" -print_final_stats=1 -artifact_prefix="$work/$name/" \
       "$work/$name" $seeds > "$work/$name.log" 2>&1; then
    status=1
    tail -n 40 "$work/$name.log"
    cp -r "$work/$name" "fuzz-failure-$name" 2>/dev/null || true
  fi
  grep -E '^stat::number_of_executed_units|^stat::peak_rss_mb' "$work/$name.log" | sed "s/^/   /"
done
exit $status
