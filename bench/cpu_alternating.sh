#!/usr/bin/env bash
# The CPU time (user + system, perf's task-clock) of `solve MODEL --json` by two builds, run in
# turn (before, after, before, ...) so that a shared machine's load falls on both alike; the
# least and the median of RUNS runs each, in ms. Where hyperfine is not installed.
#   bench/cpu_alternating.sh BEFORE/stiffmsa AFTER/stiffmsa MODEL [RUNS]
set -euo pipefail
before="$1" after="$2" model="$3" runs="${4:-40}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
cpu_ms() {
  perf stat -x, -e task-clock "$1" solve "$model" --json "$work/result.json" 2>&1 >/dev/null |
    awk -F, '/task-clock/ {print $1}'
}
for ((i = 0; i < runs; ++i)); do
  cpu_ms "$before" >> "$work/before"
  cpu_ms "$after" >> "$work/after"
done
for build in before after; do
  sort -g "$work/$build" | awk -v name="$build" '{v[NR] = $1} END {
    printf "%s: CPU ms least %.1f, median %.1f (%d runs)\n", name, v[1], v[int((NR + 1) / 2)], NR}'
done
