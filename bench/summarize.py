#!/usr/bin/env python3
"""Prints the Markdown tables of bench/README.md from the files bench/run.sh writes:
PREFIX.json (Google Benchmark), PREFIX-chain.jsonl (stiffmsa_chain), PREFIX-cli.txt and
PREFIX-sweep.jsonl (stiffmsa_sweep_throughput).

    bench/summarize.py bench/results-2026-11-21-run1 [bench/results-2026-11-21-run2 ...]

With several runs, each figure is the lowest of the runs (on a shared machine the lowest is
the least disturbed), and the spread between the runs is printed. Times are CPU times;
per-pose figures in µs.
"""
import json
import os
import sys

ROBOTS = [("6axis", "6-axis robot (industrial-6axis.yaml)"),
          ("6axis_rigid", "6-axis, links made rigid (the VJM's robot)"),
          ("gough_stewart", "Gough–Stewart (gough-stewart-6ups.yaml)"),
          ("tripteron", "3-leg tripteron (tripteron.yaml)")]
SOLVERS = ["auto", "sparse_lu", "umfpack", "klu"]
UNIT = {"ns": 1e-3, "us": 1.0, "ms": 1e3, "s": 1e6}  # to µs


def load_benchmarks(path):
    with open(path) as f:
        data = json.load(f)
    runs = {}
    for b in data["benchmarks"]:
        if b.get("run_type", "iteration") != "iteration":
            continue
        b["cpu_us"] = b["cpu_time"] * UNIT[b["time_unit"]]
        runs[b["name"]] = b
    return data.get("context", {}), runs


def lowest(dicts, key):
    """Per name, the entry with the lowest `key` over several runs, and the spreads (largest
    over lowest, minus 1) of the names every run has."""
    merged, spreads = {}, []
    for name in set().union(*dicts):
        entries = [d[name] for d in dicts if name in d]
        merged[name] = min(entries, key=lambda e: e[key])
        if len(entries) == len(dicts) > 1:
            values = [e[key] for e in entries]
            spreads.append(max(values) / min(values) - 1 if min(values) > 0 else 0)
    return merged, sorted(spreads)


def jsonl_records(prefixes, suffix):
    """(prefix, record) for every non-blank line of every PREFIX+SUFFIX file that exists."""
    for prefix in prefixes:
        if os.path.exists(prefix + suffix):
            with open(prefix + suffix) as lines:
                for line in lines:
                    if line.strip():
                        yield prefix, json.loads(line)


def chain_rows(prefixes):
    rows = {}
    for prefix, r in jsonl_records(prefixes, "-chain.jsonl"):
        rows.setdefault((r.get("source", "code"), r["solver"], r["links"]), {})[prefix] = r
    return {k: min(v.values(), key=lambda r: r["solve_s"]) for k, v in rows.items()}


def cli_rows(prefixes):
    rows = {}
    for prefix in prefixes:
        if os.path.exists(prefix + "-cli.txt"):
            for line in open(prefix + "-cli.txt"):
                model, solver, seconds, _, kib, _ = line.split()
                rows.setdefault((model, solver), []).append((float(seconds), int(kib)))
    return {k: min(v) for k, v in rows.items()}


def us(runs, name, digits=1):
    b = runs.get(name)
    return f"{b['cpu_us']:.{digits}f}" if b else "–"


def per_pose_table(runs):
    print("| model | solver | validate | topology | make_blocks | fill | factorize | solve | public `solve` "
          "| public, no refinement | internal pipeline | allocs/pose | C vs default solver | residual |")
    print("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
    for key, label in ROBOTS:
        unknowns = runs.get(f"{key}/public_solve/sparse_lu", {}).get("unknowns")
        name = f"{label}, {int(unknowns)} unknowns" if unknowns else label
        for s in SOLVERS:
            public = runs.get(f"{key}/public_solve/{s}")
            if not public:
                continue
            print(f"| {name} | {s} | {us(runs, key + '/stage:validate')} | {us(runs, key + '/stage:topology')} | {us(runs, key + '/stage:make_blocks')} "
                  f"| {us(runs, key + '/stage:fill')} | {us(runs, f'{key}/stage:factorize/{s}')} "
                  f"| {us(runs, f'{key}/stage:solve/{s}')} | **{us(runs, f'{key}/public_solve/{s}')}** "
                  f"| {us(runs, f'{key}/public_solve_refine0/{s}')} | {us(runs, f'{key}/pipeline/{s}')} "
                  f"| {public.get('allocs', 0):.0f} | {public.get('c_diff', 0):.0e} "
                  f"| {public.get('residual', 0):.0e} |")
            name = ""
        dense = runs.get(f"{key}/dense_lu")
        if dense:
            print(f"| | dense PartialPivLU | | | | | | | | | **{dense['cpu_us']:.1f}** | "
                  f"| {dense.get('err_vs_sparse', 0):.0e} | |")
    vjm = runs.get("6axis/vjm_floor")
    if vjm:
        print(f"| 6-axis, closed-form VJM floor (C and K = C⁻¹) | – | | | | | | | **{vjm['cpu_us']:.2f}** | | | "
              f"| rigid-link MSA vs VJM: {vjm.get('msa_vs_vjm', 0):.0e} | |")


def breakdown_table(runs):
    print("| model | solver | factorize | equilibrate | bare LU | condition estimate | rest | solve "
          "| bare triangular solves (7 rhs) | solve, no refinement | refinement (solve − no refinement) |")
    print("|---|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
    for key, label in ROBOTS:
        for s in SOLVERS:
            f = runs.get(f"{key}/stage:factorize/{s}")
            if not f:
                continue
            eq = runs[f"{key}/part:equilibrate"]["cpu_us"]
            lu = runs[f"{key}/part:lu_numeric/{s}"]["cpu_us"]
            cond = runs[f"{key}/part:condition_estimate/{s}"]["cpu_us"]
            solve = runs[f"{key}/stage:solve/{s}"]["cpu_us"]
            bare = runs[f"{key}/part:lu_solve/{s}"]["cpu_us"]
            once = runs[f"{key}/part:solve_refine0/{s}"]["cpu_us"]
            fc = f["cpu_us"]

            def pct(x, whole):
                return f"{x:.1f} ({100 * x / whole:.0f} %)"

            rest = fc - eq - lu - cond  # parts timed alone may add up to more than the stage

            print(f"| {key} | {s} | {fc:.1f} | {pct(eq, fc)} | {pct(lu, fc)} | {pct(cond, fc)} "
                  f"| {pct(rest, fc) if rest > 0.05 * fc else '≈ 0'} | {solve:.1f} | {pct(bare, solve)} | {pct(once, solve)} "
                  f"| {pct(solve - once, solve)} |")


def chain_gbench_table(runs):
    print("| N links | solver | whole `solve(model)`, ms | `solve(workspace, model)`, ms | µs per link (whole) "
          "| tip compliance error | C_yy error |")
    print("|--:|---|--:|--:|--:|--:|--:|")
    for n in [10, 100, 1000, 10000, 100000]:
        for s in SOLVERS:
            whole = runs.get(f"chain/solve/{s}/N:{n}")
            if not whole:
                continue
            again = runs.get(f"chain/resolve/{s}/N:{n}")
            again = f"{again['cpu_us'] / 1e3:.2f}" if again else "–"
            print(f"| {n} | {s} | {whole['cpu_us'] / 1e3:.2f} | {again} "
                  f"| {whole['cpu_us'] / n:.1f} | {whole.get('tip_err', 0):.1e} | {whole.get('Cyy_err', 0):.1e} |")


def chain_process_table(rows):
    print("| N links | solver | unknowns | whole solve, s | workspace, s | first solve, s | repeated solve, s "
          "| peak memory, MiB | model alone, MiB | KiB per link (peak) | tip error | C_yy error |")
    print("|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|")
    for r in rows.values():
        print(f"| {r['links']} | {r['solver']} | {r['unknowns']} | {r['solve_s']:.3f} | {r['workspace_s']:.3f} "
              f"| {r['first_solve_s']:.3f} | {r['repeat_solve_s']:.3f} | {r['peak_mib']:.0f} | {r['model_rss_mib']:.0f} "
              f"| {1024 * r['peak_mib'] / r['links']:.1f} | {r['tip_error']:.1e} | {r['cyy_error']:.1e} |")


def frame_table(runs):
    print("| model | solver | whole `solve(model)`, ms | `solve(workspace, model)`, ms | unknowns |")
    print("|---|---|--:|--:|--:|")
    for s in SOLVERS:
        whole = runs.get(f"frame/solve/{s}")
        if whole:
            again = runs.get(f"frame/resolve/{s}")
            again = f"{again['cpu_us'] / 1e3:.1f}" if again else "–"
            print(f"| frame, {whole.get('links', 0):.0f} beams | {s} | {whole['cpu_us'] / 1e3:.1f} "
                  f"| {again} | {whole.get('unknowns', 0):.0f} |")
    dense = runs.get("frame/dense_ldlt_of_K")
    if dense:
        print(f"| frame, K dense, LDLᵀ of every entry (node deflections within "
              f"{dense.get('u_diff', 0):.1e} of the library's) | Eigen LDLT | {dense['cpu_us'] / 1e3:.1f} | – "
              f"| {dense.get('unknowns', 0):.0f} |")


def klu_fill_table(runs):
    print("| matrix | KLU ordering | pivot tolerance | numeric factorisation, ms | nnz(A) | nnz(L + U) | fill | "
          "max error of x for A·x = A·1 (no refinement) |")
    print("|---|---|--:|--:|--:|--:|--:|--:|")
    for name in ["6axis", "tripteron", "chain_10000", "frame"]:
        for ordering in ["amd", "colamd"]:
            for tol in ["1", "0.001"]:
                b = runs.get(f"{name}/klu_fill/{ordering}/tol:{tol}")
                if b:
                    print(f"| {name} | {ordering} | {tol} | {b['cpu_us'] / 1e3:.3f} | {b['nnz_A']:.0f} "
                          f"| {b['nnz_LU']:.0f} | {b['nnz_LU'] / b['nnz_A']:.2f} | {b['x_err']:.1e} |")


def sweep_rows(prefixes):
    """Per model, every repeat of every run pooled (stiffmsa_sweep_throughput prints each repeat)."""
    pooled_keys = ["wall_s_1", "wall_s_2", "cpu_s_1", "cpu_s_2", "steal_ticks_1", "steal_ticks_2", "build_s", "solve_s"]
    rows = {}
    for _, r in jsonl_records(prefixes, "-sweep.jsonl"):
        if "pair" in r:
            continue
        row = rows.get(r["model"])
        if row is None:
            rows[r["model"]] = r
        else:
            for key in pooled_keys:
                row[key] = row[key] + r[key]
            row["make_builder_s"] = min(row["make_builder_s"], r["make_builder_s"])
    return rows


def median(values):
    v = sorted(values)
    return v[len(v) // 2] if len(v) % 2 else (v[len(v) // 2 - 1] + v[len(v) // 2]) / 2


SWEEP_LABELS = {"3rpr": "3-RPR", "tripteron": "tripteron", "delta-ss": "Delta, ball joints at both rod ends",
                "delta-us": "Delta, universal joints at the rod tops"}


def pair_rows(prefixes):
    """Per pair of models swept in turn on one thread, every repeat of every run pooled."""
    pairs = {}
    for _, r in jsonl_records(prefixes, "-sweep.jsonl"):
        if "pair" not in r:
            continue
        key = tuple(r["pair"])
        if key in pairs:
            for k in ("wall_s_first", "wall_s_second", "cpu_s_first", "cpu_s_second"):
                pairs[key][k] += r[k]
        else:
            pairs[key] = r
    return pairs


def pair_table(pairs):
    """Per pose on one thread, wall and CPU time: each model's lowest and median, and the ratio of
    the paired repeats (the first model's time over the second's, swept right after it)."""
    print("| models, in turn on one thread | time | poses | first, µs per pose: lowest (median) "
          "| second, µs per pose: lowest (median) | first / second: lowest times (median of the pairs; range) |")
    print("|---|---|--:|--:|--:|--:|")
    for (first, second), r in pairs.items():
        n = r["poses"]
        for clock in ("wall", "cpu"):
            a, b = r[f"{clock}_s_first"], r[f"{clock}_s_second"]
            paired = [x / y for x, y in zip(a, b)]
            print(f"| {SWEEP_LABELS.get(first, first)} / {SWEEP_LABELS.get(second, second)} ({r['solver']}) "
                  f"| {clock.upper() if clock == 'cpu' else clock} | {n} "
                  f"| {1e6 * min(a) / n:.1f} ({1e6 * median(a) / n:.1f}) "
                  f"| {1e6 * min(b) / n:.1f} ({1e6 * median(b) / n:.1f}) "
                  f"| {min(a) / min(b):.2f} ({median(paired):.2f}; {min(paired):.2f}–{max(paired):.2f}) |")


def sweep_tables(rows, runs):
    """Throughput with 1 and 2 threads (wall time of whole sweep() calls: lowest of the repeats,
    median in parentheses), and one pose split into building the member and solving it."""
    print("| model, grid | poses (ok) | 1 thread, poses/s | 2 threads, poses/s | per core at 2 threads, poses/s "
          "| speed-up time(1)/time(2): lowest times (median of the paired repeats; range) "
          "| CPU busy at 2 threads, cores (median) |")
    print("|---|--:|--:|--:|--:|--:|--:|")
    for key, r in rows.items():
        n = r["poses"]
        t1, t2 = r["wall_s_1"], r["wall_s_2"]
        paired = [a / b for a, b in zip(t1, t2)]
        busy = [c / w for c, w in zip(r["cpu_s_2"], t2)]
        failed = "; ".join(f"{count} {status}" for status, count in r["statuses"].items() if status != "ok")
        print(f"| {SWEEP_LABELS.get(key, key)} ({r['file']}), {r['grid']} | {n} ({r['statuses'].get('ok', 0)}"
              f"{'; ' + failed if failed else ''}) "
              f"| {n / min(t1):.0f} ({n / median(t1):.0f}) | {n / min(t2):.0f} ({n / median(t2):.0f}) "
              f"| {n / min(t2) / 2:.0f} ({n / median(t2) / 2:.0f}) "
              f"| {min(t1) / min(t2):.2f} ({median(paired):.2f}; {min(paired):.2f}–{max(paired):.2f}) "
              f"| {median(busy):.2f} |")
    print("\nOne pose on one thread, µs (lowest of the repeats):\n")
    print("| model | sweep, 1 thread | build the member (`make_builder()` once, then the builder) "
          "| `solve(workspace, member)` | the rest |")
    print("|---|--:|--:|--:|--:|")
    for key, r in rows.items():
        n = r["poses"]
        pose = 1e6 * min(r["wall_s_1"]) / n
        build = 1e6 * min(r["build_s"]) / n
        solve = 1e6 * min(r["solve_s"]) / n
        print(f"| {SWEEP_LABELS.get(key, key)}, {n} poses ({r['solver']}) | {pose:.1f} "
              f"| {build:.1f} ({100 * build / pose:.0f} %) | {solve:.1f} ({100 * solve / pose:.0f} %) "
              f"| {pose - build - solve:.1f} ({100 * (pose - build - solve) / pose:.0f} %) |")
    # The robot as a fixed model through the public `solve`: stiffmsa_bench's per-pose benchmarks
    # (CPU time, table "Per pose") have the tripteron but no 3-RPR.
    fixed, missing = [], []
    for key, r in rows.items():
        b = runs.get(f"{key}/public_solve/{r['solver']}")
        if b:
            fixed.append(f"{dict(ROBOTS).get(key, key)} {b['cpu_us']:.1f} µs per pose ({r['solver']})")
        else:
            missing.append(SWEEP_LABELS.get(key, key))
    if fixed:
        print(f"\nFixed model, public `solve` (stiffmsa_bench, CPU time, table \"Per pose\"): {', '.join(fixed)}"
              f"{'; stiffmsa_bench has no fixed ' + ', '.join(missing) if missing else ''}.")
    for key, r in rows.items():
        cpu1, cpu2 = median(r["cpu_s_1"]), median(r["cpu_s_2"])
        print(f"\n{SWEEP_LABELS.get(key, key)}: make_builder() {1e6 * r['make_builder_s']:.0f} µs once; CPU per pose "
              f"(median) {1e6 * cpu1 / r['poses']:.0f} µs on 1 thread, {1e6 * cpu2 / r['poses']:.0f} µs on 2; "
              f"steal ticks per sweep (largest) {max(r['steal_ticks_1'] + r['steal_ticks_2']):.0f}; "
              f"{len(r['wall_s_1'])} repeats.")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    prefixes = sys.argv[1:]
    loaded = [load_benchmarks(p + ".json") for p in prefixes]
    context = loaded[-1][0]
    runs, spreads = lowest([r for _, r in loaded], "cpu_us")
    print(f"Host: {context.get('num_cpus')} × {context.get('mhz_per_cpu')} MHz, {context.get('compiler', '')}, "
          f"Eigen {context.get('eigen', '')}, SuiteSparse: {context.get('suitesparse', '')}; library at "
          f"{context.get('commit', '?')}; runs: " + ", ".join(
              f"{c.get('date', '?')} (load {', '.join(f'{x:.2f}' for x in c.get('load_avg', []))})" for c, _ in loaded))
    if spreads:
        print(f"\nLowest of {len(prefixes)} runs. Spread between the runs over {len(spreads)} benchmarks: median "
              f"{100 * spreads[len(spreads) // 2]:.0f} %, 90th percentile {100 * spreads[int(0.9 * len(spreads))]:.0f} %, "
              f"largest {100 * spreads[-1]:.0f} %.")
    print("\n### Per pose (µs)\n")
    per_pose_table(runs)
    print("\n### Inside factorize and solve (µs, share of the stage)\n")
    breakdown_table(runs)
    print("\n### Chain of N beam links (Google Benchmark)\n")
    chain_gbench_table(runs)
    chain = chain_rows(prefixes)
    built = {k: v for k, v in chain.items() if k[0] == "code"}
    if built:
        print("\n### Chain of N beam links, one process each (time and peak memory)\n")
        chain_process_table(dict(sorted(built.items(), key=lambda kv: (SOLVERS.index(kv[0][1]), kv[0][2]))))
    for (source, solver, links), r in chain.items():
        if source == "file":
            print(f"\nThe {links}-link chain file read by `load_model`: {r['build_model_s']:.2f} s, "
                  f"{r['model_rss_mib']:.0f} MiB resident after reading; then `solve` ({solver}): {r['solve_s']:.2f} s; "
                  f"peak {r['peak_mib']:.0f} MiB.")
    print("\n### Frame\n")
    frame_table(runs)
    print("\n### KLU's factors against its ordering and pivot tolerance\n")
    klu_fill_table(runs)
    cli = cli_rows(prefixes)
    if cli:
        print("\n### `stiffmsa solve` on generated files (best of 3 per run)\n")
        print("| model | solver | wall time, s | peak memory, MiB |")
        print("|---|---|--:|--:|")
        for (model, solver), (seconds, kib) in cli.items():
            print(f"| {model} | {solver} | {seconds:.2f} | {kib / 1024:.0f} |")
    sweeps = sweep_rows(prefixes)
    if sweeps:
        print("\n### Sweeps (stiffmsa_sweep_throughput, wall time, not pinned to one core)\n")
        sweep_tables(sweeps, runs)
    pairs = pair_rows(prefixes)
    if pairs:
        print("\n### Sweeps of two models in turn (stiffmsa_sweep_throughput, one thread, wall time)\n")
        pair_table(pairs)


if __name__ == "__main__":
    main()
