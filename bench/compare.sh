#!/usr/bin/env bash
# The library before and after a change, in one session: builds BASELINE (a commit) in a git
# worktree under build-compare/, and the working tree in build-bench/, then alternates the two
# ROUNDS times (default 3) on one core, each pose benchmark after 0.5 s of warm-up (the first of
# a process would otherwise run cold) and repeated BENCH_REPETITIONS times (default 5) per round:
# the robots' public solve with each solver (and the
# serial robots' tree pipeline, the VJM floor), the chain of
# 10 000 and 100 000 links (one process each: time, peak memory, tip error) and the `stiffmsa
# solve` command on the 100 000-link file. This VM's timings drift from process to process and
# hour to hour, so only figures taken side by side are compared; the table gives the best of
# every measurement and their median. Results: bench/results-<date>-compare.txt (raw) and the table on stdout.
#
# Usage: bench/compare.sh BASELINE [ROUNDS]     e.g. bench/compare.sh 0847040
set -euo pipefail

root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
baseline="$(git -C "$root" rev-parse --short "${1:?usage: bench/compare.sh BASELINE [ROUNDS]}")"
rounds="${2:-3}"
repetitions="${BENCH_REPETITIONS:-5}"  # of each pose benchmark per round, 0.2 s each
base_src="$root/build-compare/$baseline"
out="$root/bench/results-${BENCH_DATE:-$(date +%F)}-compare.txt"
pin=(taskset -c "${BENCH_CPU:-0}")
targets=(stiffmsa_bench stiffmsa_chain stiffmsa_cli)

bash "$root/scripts/install-deps.sh" bench
[[ -d "$base_src" ]] || git -C "$root" worktree add --detach "$base_src" "$baseline" >/dev/null
for side in "$base_src" "$root"; do
  cmake -S "$side" -B "$side/build-bench" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DSTIFFMSA_BUILD_BENCH=ON -DSTIFFMSA_BUILD_TESTS=OFF >/dev/null
  cmake --build "$side/build-bench" -j2 --target "${targets[@]}"
done
chain_file="$root/build-bench/chain-100000.yaml"
[[ -f "$chain_file" ]] || python3 "$root/bench/make_models.py" chain 100000 >"$chain_file"

solvers_of() {  # the solvers a build knows (auto arrived with the tuning; klu needs SuiteSparse)
  local solver
  for solver in auto sparse_lu klu; do
    if "$1/bench/stiffmsa_chain" 10 "$solver" --once >/dev/null 2>&1; then printf '%s ' "$solver"; fi
  done
}
declare -A build_of=([before]="$base_src/build-bench" [after]="$root/build-bench")
declare -A solvers_on=([before]="$(solvers_of "${build_of[before]}")" [after]="$(solvers_of "${build_of[after]}")")
: >"$out"
for round in $(seq "$rounds"); do
  # Alternate which side goes first, so that a drift within a round favours neither.
  order=(before after); (( round % 2 == 0 )) && order=(after before)
  for side in "${order[@]}"; do
    dir="${build_of[$side]}"
    read -r -a solvers <<<"${solvers_on[$side]}"
    filter="^(6axis|6axis_rigid|tripteron|gough_stewart)/public_solve/($(IFS='|'; echo "${solvers[*]}"))\$|^(6axis[a-z_]*|tripteron)/pipeline/tree\$|^6axis/vjm_floor\$"
    "${pin[@]}" "$dir/bench/stiffmsa_bench" --benchmark_filter="$filter" --benchmark_min_warmup_time=0.5 \
      --benchmark_repetitions="$repetitions" --benchmark_min_time=0.2 --benchmark_format=json 2>/dev/null |
      python3 -c "import json, sys
scale = {'ns': 1e-3, 'us': 1.0, 'ms': 1e3, 's': 1e6}
for b in json.load(sys.stdin)['benchmarks']:
    if b.get('run_type', 'iteration') == 'iteration':
        print('$side', 'pose', b.get('run_name', b['name']), b['cpu_time'] * scale[b['time_unit']], 'us')" | tee -a "$out"
    for n in 10000 100000; do
      for s in "${solvers[@]}"; do
        "${pin[@]}" "$dir/bench/stiffmsa_chain" "$n" "$s" --once |
          python3 -c "import json, sys
d = json.loads(sys.stdin.read())
print('$side', 'chain', f\"{d['links']}/{d['solver']}\", d['solve_s'], 's', d['peak_mib'], 'MiB', d['tip_error'])" | tee -a "$out"
      done
    done
    for s in "${solvers[@]}"; do
      /usr/bin/time -f "$side cli chain-100000/$s %e s %M KiB" "${pin[@]}" \
        "$dir/stiffmsa" solve "$chain_file" --solver "$s" --json "$dir/chain-100000-result.json" \
        2>&1 >/dev/null | tail -1 | tee -a "$out"
    done
  done
done

python3 - "$out" <<'PY'
import statistics, sys
best, values = {}, {}
for line in open(sys.argv[1]):
    f = line.split()
    side, kind, name, value = f[0], f[1], f[2], float(f[3])
    extra = ""
    if kind == "chain": extra = f"{float(f[5]):.0f} MiB, tip error {f[7]}"
    if kind == "cli": extra = f"{int(f[5]) / 1024:.0f} MiB"
    key = (kind, name)
    values.setdefault(key, {}).setdefault(side, []).append(value)
    if side not in best.setdefault(key, {}) or value < best[key][side][0]:
        best[key][side] = (value, f[4], extra)
# The best of every measurement, and the median beside it: one figure alone can be off by 2×
# on this VM.
print("| what | before: best (median) | after: best (median) | after/before, best |")
print("|---|--:|--:|--:|")
for (kind, name), sides in sorted(best.items()):
    b, a = sides.get("before"), sides.get("after")
    def show(side, x):
        if not x: return "–"
        median = statistics.median(values[(kind, name)][side])
        return f"{x[0]:.4g} ({median:.4g}) {x[1]}" + (f" ({x[2]})" if x[2] else "")
    ratio = f"{a[0] / b[0]:.2f}" if a and b else "–"
    print(f"| {kind} {name} | {show('before', b)} | {show('after', a)} | {ratio} |")
PY
