#!/usr/bin/env bash
# The command's fixed costs, two builds side by side in one run: `stiffmsa --version` (the start:
# loading shared libraries), `stiffmsa solve --json` of the 1 015-beam lattice
# (make_models.py lattice 6 6 7: 7×7×8 nodes, bottom clamped) and of the 6-axis example. Wall and CPU times from
# hyperfine (alternating the builds within each benchmark is hyperfine's order: one build's runs,
# then the other's), and instructions from callgrind, which the machine's load does not change.
#   bench/startup_lattice.sh BEFORE/stiffmsa AFTER/stiffmsa > bench/results-DATE-startup-lattice.txt
set -euo pipefail
before="$1" after="$2"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
python3 "$root/bench/make_models.py" lattice 6 6 7 > "$work/lattice.yaml"
six_axis="$root/examples/industrial-6axis.yaml"
echo "# $(date -u +%FT%TZ) $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "# before: $before"
echo "# after:  $after"
echo "# load before: $(uptime)"
for run in 1 2; do
  hyperfine -N --warmup 20 --runs 300 --style basic "$before --version" "$after --version" 2>&1 | grep -E 'Benchmark|Time|Range'
  hyperfine -N --warmup 5 --runs 60 --style basic "$before solve $work/lattice.yaml --json $work/before.json" \
    "$after solve $work/lattice.yaml --json $work/after.json" 2>&1 | grep -E 'Benchmark|Time|Range'
  hyperfine -N --warmup 5 --runs 100 --style basic "$before solve $six_axis --json $work/before-6axis.json" \
    "$after solve $six_axis --json $work/after-6axis.json" 2>&1 | grep -E 'Benchmark|Time|Range'
done
cmp "$work/before.json" "$work/after.json" && cmp "$work/before-6axis.json" "$work/after-6axis.json" &&
  echo "result files: the same bytes"
for program in "$before" "$after"; do
  for args in "--version" "solve $work/lattice.yaml --json $work/cg.json"; do
    echo "instructions, $program $args: $(valgrind --tool=callgrind --callgrind-out-file="$work/cg.out" \
      $program $args 2>&1 >/dev/null | sed -n 's/.*Collected : //p')"
  done
  # The objects the dynamic loader maps (the executable's libraries, and those of the modules it
  # loads with dlopen), for the version and for a solve.
  for args in "--version" "solve $work/lattice.yaml --json $work/cg.json"; do
    echo "shared objects mapped, $program $args: $(LD_DEBUG=files $program $args 2>&1 >/dev/null |
      grep -c 'generating link map')"
  done
done
echo "# load after: $(uptime)"
