#!/usr/bin/env bash
# The command's fixed costs, two builds side by side in one run: `stiffmsa --version` (the start:
# loading shared libraries), `stiffmsa solve --json` of the 1 015-beam lattice
# (make_models.py lattice 6 6 7: 7×7×8 nodes, bottom clamped) and of the 6-axis example. CPU
# (perf's task-clock: user + system) and wall time (bash's clock around a run) of whole processes,
# the two builds run in turn (before, after, before, ...) so that a shared machine's load falls
# on both alike, least and median of RUNS each; and instructions from callgrind, which the
# machine's load does not change. Needs perf and valgrind (no hyperfine).
#   bench/startup_lattice.sh BEFORE/stiffmsa AFTER/stiffmsa [RUNS] > bench/results-DATE-startup-lattice.txt
set -euo pipefail
before="$1" after="$2" runs="${3:-40}"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
python3 "$root/bench/make_models.py" lattice 6 6 7 > "$work/lattice.yaml"
six_axis="$root/examples/industrial-6axis.yaml"
echo "# $(date -u +%FT%TZ) $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "# before: $before"
echo "# after:  $after"
echo "# load before: $(uptime)"

# "CPU-ms wall-ms" of the command line: its CPU under perf, its wall time in a run of its own
# (perf's duration_time reads 0 for a process of a millisecond; this one includes the shell's
# fork and exec, the same for both builds).
times_ms() {
  local cpu start end
  cpu=$(perf stat -x, -e task-clock "$@" 2>&1 >/dev/null | awk -F, '/task-clock/ {print $1}')
  start=$EPOCHREALTIME
  "$@" >/dev/null
  end=$EPOCHREALTIME
  echo "$cpu $(awk -v s="$start" -v e="$end" 'BEGIN {printf "%.3f", (e - s) * 1000}')"
}
# Least and median of each column of a file of "CPU wall" lines.
summarize() {
  for column in 1 2; do
    cut -d' ' -f"$column" "$1" | sort -g | awk -v what="$([[ $column == 1 ]] && echo CPU || echo wall)" \
      '{v[NR] = $1} END {printf "  %s ms least %.2f, median %.2f (%d runs)\n", what, v[1], v[int((NR + 1) / 2)], NR}'
  done
}
declare -A cases=(
  [version]="--version"
  [lattice]="solve $work/lattice.yaml --json $work/RESULT.json"
  [6axis]="solve $six_axis --json $work/RESULT-6axis.json"
)
for name in version lattice 6axis; do
  for ((i = 0; i < runs; ++i)); do
    for build in before after; do
      program=$([[ $build == before ]] && echo "$before" || echo "$after")
      # shellcheck disable=SC2086 # the case's arguments are words
      times_ms "$program" ${cases[$name]//RESULT/$build} >> "$work/$name.$build"
    done
  done
  for build in before after; do
    echo "$name, $build:"
    summarize "$work/$name.$build"
  done
done
cmp "$work/before.json" "$work/after.json" && cmp "$work/before-6axis.json" "$work/after-6axis.json" &&
  echo "result files: the same bytes"
for program in "$before" "$after"; do
  for args in "--version" "solve $work/lattice.yaml --json $work/cg.json"; do
    # shellcheck disable=SC2086
    echo "instructions, $program $args: $(valgrind --tool=callgrind --callgrind-out-file="$work/cg.out" \
      $program $args 2>&1 >/dev/null | sed -n 's/.*Collected : //p')"
  done
  # The objects the dynamic loader maps (the executable's libraries, and those of the modules it
  # loads with dlopen), for the version and for a solve.
  for args in "--version" "solve $work/lattice.yaml --json $work/cg.json"; do
    # shellcheck disable=SC2086
    echo "shared objects mapped, $program $args: $(LD_DEBUG=files $program $args 2>&1 >/dev/null |
      grep -c 'generating link map')"
  done
done
echo "# load after: $(uptime)"
