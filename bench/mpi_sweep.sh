#!/usr/bin/env bash
# Sweeps over MPI ranks against one process, on the same grid (bench/README.md, "Sweeps over MPI
# ranks"): the 3-RPR example over a grid of GRID poses per axis, rows written to a CSV, run as
#   one process with 2 threads; 1 rank (mpirun -n 1 --bind-to none) with 2 threads;
#   2 ranks bound to a core each (Open MPI's default for 2 ranks), 1 thread each;
#   2 ranks unbound with 2 threads each (4 threads on 2 cores);
# alternated, REPEATS times each, each in a session of its own (setsid): with the kernel's
# autogroup scheduling, the ranks mpirun starts get a CPU share of their own on a loaded
# machine, and a process started from the shell would compete at a disadvantage. Each run prints the sweep's own time (solving and writing, not
# start-up) and, over ranks, rank 0's CPU time for receiving and writing rows.
# Raw output to bench/results-<date>-mpi.txt, then the best of each mode.
# Environment: BUILD_DIR (a build with -DSTIFFMSA_WITH_MPI=ON; default build), GRID (default
#   201), REPEATS (default 5), BENCH_DATE, BLOCK (poses per block, default 4096).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
grid="${GRID:-201}"
repeats="${REPEATS:-5}"
block="${BLOCK:-4096}"
out="$root/bench/results-${BENCH_DATE:-$(date +%F)}-mpi.txt"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
sweep=("$build/stiffmsa" sweep "$root/examples/planar-3rpr-parametric.yaml" --grid "x=0.1:0.9:$grid"
       --grid "y=0.05:0.8:$grid" --quiet --block "$block" --csv "$work/rows.csv")
declare -A modes=(
  [process-2t]="setsid -w ${sweep[*]} --threads 2"
  [rank1-2t]="setsid -w mpirun -n 1 --bind-to none ${sweep[*]} --threads 2"
  [ranks2-bound-1t]="setsid -w mpirun -n 2 ${sweep[*]} --threads 1"
  [ranks2-unbound-2t]="setsid -w mpirun -n 2 --bind-to none ${sweep[*]} --threads 2"
)
{
  echo "== $(date -u +%FT%TZ) $(git -C "$root" log -1 --format=%h) grid ${grid}x${grid} block $block"
  echo "== machine: $(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2); $(uptime)"
  for ((r = 1; r <= repeats; r++)); do
    for mode in process-2t rank1-2t ranks2-bound-1t ranks2-unbound-2t; do
      start=$(date +%s.%N)
      text="$(${modes[$mode]})"
      end=$(date +%s.%N)
      echo "-- $mode repeat $r process-wall $(awk "BEGIN { print $end - $start }") s"
      echo "$text" | grep -E "poses over|rank 0 spent"
    done
  done
} | tee "$out"
/usr/bin/python3 - "$out" <<'PY'
import re, sys
best = {}
mode = None
for line in open(sys.argv[1]):
    m = re.match(r"-- (\S+) repeat \d+ process-wall (\S+) s", line)
    if m:
        mode, wall = m.group(1), float(m.group(2))
        continue
    m = re.search(r"(\d+) poses over .* in (\S+) s", line)
    if m and mode:
        poses, seconds = int(m.group(1)), float(m.group(2))
        b = best.setdefault(mode, {"seconds": 1e9, "wall": 1e9, "root_us": None})
        b["poses"] = poses
        b["seconds"] = min(b["seconds"], seconds)
        b["wall"] = min(b["wall"], wall)
    m = re.search(r"\(([\d.e+-]+) us per row\)", line)
    if m and mode:
        r = float(m.group(1))
        b = best[mode]
        b["root_us"] = r if b["root_us"] is None else min(b["root_us"], r)
print("| mode | poses | best sweep time (s) | poses/s | best process wall (s) | rank 0 CPU per row (us) |")
print("| --- | --- | --- | --- | --- | --- |")
for mode, b in best.items():
    root = "" if b["root_us"] is None else "%.3g" % b["root_us"]
    print("| %s | %d | %.3f | %.0f | %.2f | %s |" % (mode, b["poses"], b["seconds"], b["poses"] / b["seconds"], b["wall"], root))
PY
