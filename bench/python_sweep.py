"""Per-pose time of a sweep from Python against the stiffmsa command, for the same sweep.

    .venv/bin/python bench/python_sweep.py [--cli build/stiffmsa] [--rounds 7] [--threads 1 2]

Each round runs, alternated, `stiffmsa sweep MODEL --grid ... --csv OUT --quiet` as a process
(wall time: start-up, reading the model, the sweep, writing the CSV and the summary) and, in
this process, what a Python user does for the same files: load_family, sweep, write_csv,
write_summary. Both also report the sweep's own wall time (the summary's `seconds`,
SweepResult.seconds). Prints the best (smallest) of the rounds per pose, in µs, as a Markdown
table.
"""

import argparse
import json
import platform
import subprocess
import tempfile
import time
from pathlib import Path

import stiffmsa

ROOT = Path(__file__).resolve().parents[1]
SWEEPS = {
    "3-RPR": (ROOT / "examples" / "planar-3rpr-parametric.yaml", {"x": (0.3, 0.6, 101), "y": (0.2, 0.45, 101)}),
    "tripteron": (ROOT / "examples" / "tripteron-parametric.yaml", {"px": (0.1, 0.4, 71), "py": (0.1, 0.4, 71)}),
}


def cli_round(cli, model, grid, threads, folder):
    csv = folder / "cli.csv"
    arguments = [str(cli), "sweep", str(model), "--csv", str(csv), "--quiet", "--threads", str(threads)]
    for name, (start, stop, count) in grid.items():
        arguments += ["--grid", f"{name}={start!r}:{stop!r}:{count}"]
    begin = time.perf_counter()
    subprocess.run(arguments, check=True, stdout=subprocess.DEVNULL)
    wall = time.perf_counter() - begin
    return wall, json.loads((folder / "cli.summary.json").read_text())["seconds"]


def python_round(model, grid, threads, folder):
    begin = time.perf_counter()
    rows = stiffmsa.load_family(model).sweep(grid=grid, threads=threads)
    rows.write_csv(folder / "python.csv")
    rows.write_summary(folder / "python.summary.json", csv="python.csv")
    wall = time.perf_counter() - begin
    return wall, rows.seconds


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cli", type=Path, default=ROOT / "build" / "stiffmsa")
    parser.add_argument("--rounds", type=int, default=7)
    parser.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    args = parser.parse_args()
    print(f"python {platform.python_version()}, {platform.machine()}, {platform.processor() or '?'}")
    print("| sweep | poses | threads | runner | whole call, µs/pose | sweep alone, µs/pose | Python / CLI (whole) |")
    print("| --- | ---: | ---: | --- | ---: | ---: | ---: |")
    with tempfile.TemporaryDirectory() as temporary:
        folder = Path(temporary)
        for label, (model, grid) in SWEEPS.items():
            poses = 1
            for _, _, count in grid.values():
                poses *= count
            for threads in args.threads:
                cli_best = python_best = (float("inf"), float("inf"))
                for _ in range(args.rounds):
                    cli_best = min(cli_best, cli_round(args.cli, model, grid, threads, folder))
                    python_best = min(python_best, python_round(model, grid, threads, folder))
                if (folder / "cli.csv").read_bytes() != (folder / "python.csv").read_bytes():
                    raise SystemExit(f"{label}: the CSVs differ")
                for runner, (wall, sweep) in (("`stiffmsa sweep`", cli_best), ("Python", python_best)):
                    ratio = f"{python_best[0] / cli_best[0]:.3f}" if runner == "Python" else ""
                    print(f"| {label} | {poses} | {threads} | {runner} | {1e6 * wall / poses:.1f} | "
                          f"{1e6 * sweep / poses:.1f} | {ratio} |")


if __name__ == "__main__":
    main()
