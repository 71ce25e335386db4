#!/usr/bin/env bash
# Configures and builds the benchmarks in build-bench/, then runs them pinned to one core:
#   1. stiffmsa_bench (Google Benchmark): per pose, stage by stage, the dense-LU baseline, the
#      VJM floor, the chain of N links and the 960-beam frame; console output, and JSON saved
#      to bench/results-<date>.json;
#   2. stiffmsa_chain, one process per chain size and solver: time, peak memory (VmHWM) and
#      tip accuracy, saved to bench/results-<date>-chain.jsonl;
#   3. the `stiffmsa solve` command, result file written, on generated model files
#      (bench/make_models.py): the 100 000-link chain and the frame, wall time and peak memory
#      from /usr/bin/time; and the chain file read by stiffmsa_chain, which times load_model
#      apart from the solve;
#   4. stiffmsa_sweep_throughput on both cores: sweeps of the parametric examples over fixed grids
#      with 1 and 2 threads (poses/s, speed-up of the second core), the per-pose split
#      between building the member and solving it, and the two Delta robots in turn on one
#      thread, saved to bench/results-<date>-sweep.jsonl;
#   5. the tables of bench/README.md, from those files (bench/summarize.py).
#
# Usage: bench/run.sh [Google Benchmark options, e.g. --benchmark_filter=6axis]
# Environment: BENCH_CPU (core to pin to, default 0), BENCH_DATE (default today), BENCH_RUN
#   (a suffix for the result files, e.g. run1), BUILD_DIR (default build-bench), SKIP_CHAIN=1,
#   SKIP_CLI=1, SKIP_SWEEP=1 to leave parts 2, 3 and 4 out; BENCH_SWEEP_CPUS (cores for part 4,
#   default 0,1), SWEEP_REPEATS (default 7); FRAME3DD, the path of a frame3dd program built
#   elsewhere, adds Frame3DD against `stiffmsa solve` on the frame to part 3.
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${BUILD_DIR:-$root/build-bench}"
cpu="${BENCH_CPU:-0}"
out="$root/bench/results-${BENCH_DATE:-$(date +%F)}${BENCH_RUN:+-$BENCH_RUN}"
pin=(taskset -c "$cpu")

bash "$root/scripts/install-deps.sh" bench
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DSTIFFMSA_BUILD_BENCH=ON -DSTIFFMSA_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j2 --target stiffmsa_bench stiffmsa_chain stiffmsa_cli stiffmsa_sweep_throughput

# The library measured: the last commit that changed its sources, and whether src/ or
# include/ differ from it.
commit="$(git -C "$root" log -1 --format=%h -- src include CMakeLists.txt 2>/dev/null || echo unknown)"
if [[ -n "$(git -C "$root" status --porcelain -- src include 2>/dev/null)" ]]; then commit="$commit+local-changes"; fi
echo "== library at $commit; machine: $(uptime)"
echo "== 1. stiffmsa_bench"
"${pin[@]}" "$build/bench/stiffmsa_bench" --benchmark_format=console --benchmark_context=commit="$commit" \
  --benchmark_out="$out.json" --benchmark_out_format=json "$@"

# The solvers this build has (umfpack and klu need SuiteSparse).
solvers=(auto sparse_lu)
for solver in umfpack klu; do
  if "$build/bench/stiffmsa_chain" 10 "$solver" --once >/dev/null 2>&1; then solvers+=("$solver"); fi
done
if [[ -z "${SKIP_CHAIN:-}" ]]; then
  echo "== 2. chain scaling, one process per N (JSON lines)"
  : >"$out-chain.jsonl"
  for solver in "${solvers[@]}"; do
    for n in 10 100 1000 10000 100000; do
      "${pin[@]}" "$build/bench/stiffmsa_chain" "$n" "$solver" | tee -a "$out-chain.jsonl"
    done
  done
fi

if [[ -z "${SKIP_CLI:-}" ]]; then
  echo "== 3. stiffmsa solve on generated files, result file written (best of 3)"
  python3 "$root/bench/make_models.py" chain 100000 >"$build/chain-100000.yaml"
  python3 "$root/bench/make_models.py" frame 5 5 10 >"$build/frame-5x5x10.yaml"
  : >"$out-cli.txt"
  for model in chain-100000 frame-5x5x10; do
    for solver in "${solvers[@]}"; do
      for run in 1 2 3; do
        /usr/bin/time -f "$model $solver %e s %M KiB" "${pin[@]}" \
          "$build/stiffmsa" solve "$build/$model.yaml" --solver "$solver" --json "$build/$model-result.json" \
          2>&1 >/dev/null | tail -1
      done | sort -k3 -g | head -1 | tee -a "$out-cli.txt"
    done
  done
  echo "== 3b. the same chain file read with load_model, then solved (stiffmsa_chain)"
  "${pin[@]}" "$build/bench/stiffmsa_chain" "$build/chain-100000.yaml" auto --once \
    | tee -a "$out-chain.jsonl"
  # Frame3DD is not packaged for Debian: measured only where FRAME3DD names a frame3dd program.
  if [[ -n "${FRAME3DD:-}" ]]; then
    echo "== 3c. the frame: stiffmsa solve against Frame3DD, whole process (bench/frame3dd_compare.py)"
    python3 "$root/bench/frame3dd_compare.py" "$FRAME3DD" --stiffmsa "$build/stiffmsa" --runs 7 \
      --cpu "$cpu" | tee "$out-frame3dd.txt"
  fi
fi

if [[ -z "${SKIP_SWEEP:-}" ]]; then
  # Not pinned to one core like the rest: the point is what the second core adds.
  echo "== 4. sweeps with 1 and 2 threads (JSON lines); machine: $(uptime)"
  taskset -c "${BENCH_SWEEP_CPUS:-0,1}" "$build/bench/stiffmsa_sweep_throughput" --repeats "${SWEEP_REPEATS:-7}" \
    | tee "$out-sweep.jsonl"
fi

echo "== 5. tables"
python3 "$root/bench/summarize.py" "$out"
