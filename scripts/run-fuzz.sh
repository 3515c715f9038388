#!/usr/bin/env bash
# Runs every libFuzzer binary in DIR (or those named in FUZZ_TARGETS) starting from
# its seed corpus in fuzz/corpus/<name>/ (never modified: new inputs go to a work copy):
#   run-fuzz.sh DIR SECONDS        each for SECONDS (`make fuzz`, the short run)
#   run-fuzz.sh DIR 0 RUNS         each to RUNS executions
#   run-fuzz.sh DIR SECONDS RUNS   each to RUNS executions or for SECONDS, whichever ends first
#                                  (`make fuzz-long`: 10^7 or an hour)
# fuzz/<name>.options holds a target's own flags. After each target: executions, exec/s, coverage (libFuzzer's cov: and ft: of its last line).
set -euo pipefail
dir=${1:?usage: run-fuzz.sh FUZZER_DIR SECONDS [RUNS]}
seconds=${2:-30}
runs=${3:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
status=0
for fuzzer in "$dir"/*; do
  [ -x "$fuzzer" ] || continue
  name=$(basename "$fuzzer")
  if [ -n "${FUZZ_TARGETS:-}" ] && [[ " $FUZZ_TARGETS " != *" $name "* ]]; then continue; fi
  mkdir -p "$work/$name"
  seeds="fuzz/corpus/$name"
  [ -d "$seeds" ] || seeds=""
  if [ -n "$runs" ] && [ "$seconds" -gt 0 ]; then
    limit=(-runs="$runs" -max_total_time="$seconds")
    echo "== $name ($runs executions or $seconds s)"
  elif [ -n "$runs" ]; then
    limit=(-runs="$runs")
    echo "== $name ($runs executions)"
  else
    limit=(-max_total_time="$seconds")
    echo "== $name ($seconds s)"
  fi
  # fuzz/<name>.options: extra libFuzzer flags, one a line (the frame fuzzers' -max_len).
  options=()
  [ -f "fuzz/$name.options" ] && mapfile -t options < "fuzz/$name.options"
  if ! "$fuzzer" "${limit[@]}" "${options[@]}" -print_final_stats=1 -artifact_prefix="$work/$name/" \
       "$work/$name" $seeds > "$work/$name.log" 2>&1; then
    status=1
    tail -n 40 "$work/$name.log"
    cp -r "$work/$name" "fuzz-failure-$name" 2>/dev/null || true
  fi
  grep -E '^stat::number_of_executed_units|^stat::average_exec_per_sec|^stat::peak_rss_mb' "$work/$name.log" |
    sed "s/^/   /"
  grep -E '^#[0-9]+' "$work/$name.log" | tail -n 1 | sed "s/^/   last: /"
done
exit $status
