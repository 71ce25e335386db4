#!/usr/bin/env python3
"""Times `stiffmsa solve` against Frame3DD on the same building frame, whole process against whole
process, and checks that the two give the same node displacements.

    bench/frame3dd_compare.py [FRAME3DD] [--stiffmsa STIFFMSA] [--runs N] [--cpu CPU]
                              [--size NX NY STOREYS] [--tolerance REL] [--keep DIR]

FRAME3DD is the path of a frame3dd program (default: $FRAME3DD), STIFFMSA that of the stiffmsa
command line program (default: $STIFFMSA, else build/stiffmsa). Frame3DD is not part of this
repository and is not packaged for Debian: build it elsewhere from its C sources
(`gcc -O2 -o frame3dd *.c -lm`).

The frame is make_models.py's (default 5 5 10: 960 beams, 396 nodes); make_models.py writes it
as a stiffmsa model and as a Frame3DD .3dd file into a temporary directory. Each program then
runs N times (default 3), alternately, pinned with `taskset -c CPU` (default 1), after one
untimed run of each whose results are compared:

- Frame3DD: `frame3dd -i frame.3dd -o frame.out -q`, in the temporary directory, with
  FRAME3DD_OUTDIR set to it (Frame3DD writes its plot and mesh files there); SI units. Its
  untimed run reads frame_mm.fmm, the same frame in N and mm: an input file named *.fmm makes
  Frame3DD also write frame_mm_out.m, whose displacements have 7 significant digits (frame.out
  has six decimals); it prints any value below 1e-8 as 0, in mm far below the translations,
  while a rotation below 1e-8 rad printed as 0 is compared as equal to one of ours below it.
- stiffmsa: `stiffmsa solve frame.yaml --json frame.json`, standard output discarded.

Times are wall-clock times of the whole process (start to exit, including reading the model
and writing the results); peak memory is the maximum resident set size, from /usr/bin/time when
it is installed, else from the kernel's accounting of the child. The displacements compared are
every node's [dx, dy, dz, rx, ry, rz]: Frame3DD's against the deflection of the stiffmsa link
ends at that node. The largest difference of the translations is given relative to the largest
translation, that of the rotations relative to the largest rotation; the script exits with
status 1 if either exceeds --tolerance (default 1e-6), 2 if a program fails. --keep DIR
keeps the models and both programs' output files in DIR.
"""
import argparse
import json
import os
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import make_models  # beside this file

BENCH = os.path.dirname(os.path.abspath(__file__))


def write_models(directory, size):
    for name, lines in [("frame.yaml", make_models.frame(*size)),
                        ("frame.3dd", make_models.frame3dd(*size)),
                        ("frame_mm.fmm", make_models.frame3dd(*size, mm=True))]:
        with open(os.path.join(directory, name), "w") as f:
            f.write("\n".join(lines) + "\n")


def run(command, directory, cpu, env=None):
    """Runs command pinned to cpu in directory; returns (wall seconds, peak RSS in MiB)."""
    command = ["taskset", "-c", str(cpu)] + command
    time_file = os.path.join(directory, "time.txt")
    gnu_time = os.path.exists("/usr/bin/time")
    if gnu_time:
        command = ["/usr/bin/time", "-f", "%M", "-o", time_file] + command
    start = time.perf_counter()
    child = subprocess.Popen(command, cwd=directory, env=env, stdin=subprocess.DEVNULL,
                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(child.pid, 0)
    wall = time.perf_counter() - start
    child.returncode = os.waitstatus_to_exitcode(status)
    stderr = child.stderr.read().decode(errors="replace")
    child.stderr.close()
    if child.returncode != 0:
        print(f"failed ({child.returncode}): {' '.join(command)}\n{stderr}", file=sys.stderr)
        sys.exit(2)
    if gnu_time:
        with open(time_file) as f:
            peak_kib = int(f.read().split()[-1])
    else:
        peak_kib = usage.ru_maxrss
    return wall, peak_kib / 1024


def frame3dd_displacements(path, length_unit):
    """Node displacements [dx, dy, dz, rx, ry, rz] of load case 1 from Frame3DD's m-file, in m."""
    with open(path) as f:
        text = f.read()
    block = re.search(r"^D1=\[(.*?)\]'", text, re.S | re.M)
    if not block:
        sys.exit(f"no displacements (D1=[...]') in {path}")
    rows = [r.split() for r in block.group(1).split(";") if r.strip()]
    return [[float(v) * (length_unit if i < 3 else 1.0) for i, v in enumerate(r)] for r in rows]


def frame3dd_out(path):
    """The displacement table (m, six decimals) and the RMS equilibrium error of frame.out."""
    with open(path) as f:
        text = f.read()
    error = re.search(r"E Q U I L I B R I U M\s+E R R O R:\s*(\S+)", text)
    table = text.split("N O D E   D I S P L A C E M E N T S", 1)[1].split("F R A M E", 1)[0]
    rows = {int(m.group(1)): [float(v) for v in m.group(2).split()]
            for m in re.finditer(r"^\s*(\d+)((?:\s+-?\d+\.\d+){6})\s*$", table, re.M)}
    return rows, error.group(1) if error else "?"


def stiffmsa_displacements(model, result):
    """Per point of the model, in model order: the deflections of the link ends there."""
    with open(model) as f:
        text = f.read()
    points = re.findall(r"^  (\w+): \[", text.split("\nlinks:", 1)[0], re.M)
    ends = {p: [] for p in points}
    with open(result) as f:
        link_ends = json.load(f)["link_ends"]
    for link, a, b in re.findall(r"^  (\w+): \{type: beam, from: (\w+), to: (\w+),", text, re.M):
        ends[a].append(link_ends[link]["from"]["deflection"])
        ends[b].append(link_ends[link]["to"]["deflection"])
    return [ends[p] for p in points]


def compare(reference, ours):
    """Largest difference relative to the largest value, for translations and for rotations.
    Frame3DD prints a value below 1e-8 of its unit (mm for the translations of the mm run,
    rad for the rotations) as 0: there, a value of ours below that counts as equal."""
    out = []
    for part, printed_as_zero in ((slice(0, 3), 1e-11), (slice(3, 6), 1e-8)):
        largest = max(abs(v) for node in ours for end in node for v in end[part])
        worst = max(0.0 if a == 0 and abs(b) < printed_as_zero else abs(a - b)
                    for ref, node in zip(reference, ours) for end in node
                    for a, b in zip(ref[part], end[part]))
        out.append((worst / largest, largest))
    return out


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("frame3dd", nargs="?", default=os.environ.get("FRAME3DD"))
    parser.add_argument("--stiffmsa", default=os.environ.get("STIFFMSA",
                        os.path.join(os.path.dirname(BENCH), "build", "stiffmsa")))
    parser.add_argument("--runs", type=int, default=3)
    parser.add_argument("--cpu", type=int, default=1)
    parser.add_argument("--size", nargs=3, type=int, default=[5, 5, 10],
                        metavar=("NX", "NY", "STOREYS"))
    parser.add_argument("--tolerance", type=float, default=1e-6)
    parser.add_argument("--keep", metavar="DIR", help="work in DIR (created) and keep its files")
    args = parser.parse_args()
    if not args.frame3dd:
        parser.error("give the frame3dd program's path (or set FRAME3DD)")
    frame3dd, stiffmsa = (os.path.abspath(p) for p in (args.frame3dd, args.stiffmsa))
    for p in (frame3dd, stiffmsa):
        if not os.access(p, os.X_OK):
            parser.error(f"not an executable: {p}")

    directory = args.keep or tempfile.mkdtemp(prefix="frame3dd_compare")
    os.makedirs(directory, exist_ok=True)
    try:
        size = args.size
        write_models(directory, size)
        env = dict(os.environ, FRAME3DD_OUTDIR=directory)
        f3dd_mm = [frame3dd, "-i", "frame_mm.fmm", "-o", "frame_mm.out", "-q"]
        f3dd = [frame3dd, "-i", "frame.3dd", "-o", "frame.out", "-q"]
        ours = [stiffmsa, "solve", "frame.yaml", "--json", "frame.json"]

        # Untimed runs (they also warm the page cache), whose results are compared.
        run(f3dd_mm, directory, args.cpu, env)
        run(ours, directory, args.cpu)
        times = {"Frame3DD": [], "stiffmsa": []}
        for _ in range(args.runs):
            if os.path.exists(os.path.join(directory, "frame.out")):  # Frame3DD appends to it
                os.remove(os.path.join(directory, "frame.out"))
            times["Frame3DD"].append(run(f3dd, directory, args.cpu, env))
            times["stiffmsa"].append(run(ours, directory, args.cpu))

        reference = frame3dd_displacements(os.path.join(directory, "frame_mm_out.m"), 1e-3)
        by_point = stiffmsa_displacements(os.path.join(directory, "frame.yaml"),
                                          os.path.join(directory, "frame.json"))
        if len(reference) != len(by_point):
            sys.exit(f"{len(reference)} Frame3DD nodes, {len(by_point)} stiffmsa points")
        (translation, max_t), (rotation, max_r) = compare(reference, by_point)
        ends_spread = max(abs(a - b) for node in by_point for end in node[1:]
                          for a, b in zip(node[0], end))
        # The timed SI run's table (six decimals) against the mm run: both computed the same frame.
        table, equilibrium = frame3dd_out(os.path.join(directory, "frame.out"))
        table_diff = max((abs(a - b) for n, row in table.items()
                          for a, b in zip(row, reference[n - 1])), default=float("inf"))
        _, mm_equilibrium = frame3dd_out(os.path.join(directory, "frame_mm.out"))
    finally:
        if not args.keep:
            shutil.rmtree(directory, ignore_errors=True)

    print(f"frame {'x'.join(map(str, size))}: {len(reference)} nodes; {args.runs} runs each, alternating, "
          f"pinned to CPU {args.cpu}; whole process, wall time")
    print("| program | best s | median s | peak MiB |")
    print("| --- | ---: | ---: | ---: |")
    for name, runs in times.items():
        walls = [w for w, _ in runs]
        print(f"| {name} | {min(walls):.4f} | {statistics.median(walls):.4f} | "
              f"{max(m for _, m in runs):.1f} |")
    best = min(w for w, _ in times["Frame3DD"]) / min(w for w, _ in times["stiffmsa"])
    median = statistics.median(w for w, _ in times["Frame3DD"]) / \
        statistics.median(w for w, _ in times["stiffmsa"])
    print(f"Frame3DD / stiffmsa: x{best:.2f} (best), x{median:.2f} (median)")
    print(f"displacements, largest |difference| / largest |value|: translations {translation:.2e} "
          f"(of {max_t:.4e} m), rotations {rotation:.2e} (of {max_r:.4e} rad); "
          f"stiffmsa's link ends at a node differ by {ends_spread:.1e} at most")
    print(f"Frame3DD's RMS relative equilibrium error: {equilibrium} (SI run), "
          f"{mm_equilibrium} (mm); "
          f"its SI output table (6 decimals) within {table_diff:.1e} of the mm run's values")
    if max(translation, rotation) > args.tolerance or table_diff > 1e-6:
        print(f"DISAGREE: more than {args.tolerance:g} relative")
        return 1
    print(f"agree within {args.tolerance:g} relative")
    return 0


if __name__ == "__main__":
    sys.exit(main())
