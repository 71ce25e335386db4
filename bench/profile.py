#!/usr/bin/env python3
"""Profiles a command with perf (DWARF call graphs, so the library's inlined frames count) and
prints the inclusive share of the stages of stiffmsa that the README's analysis names.

    bench/profile.py [--freq HZ] [--root REGEX] OUT.data -- COMMAND [ARGS...]

Shares are of all samples, or of those under --root (a symbol regex). Examples, pinned to one
core:

    bench/profile.py --root '^stiffmsa::solve$' /tmp/6axis.data -- taskset -c 0 \\
        build-bench/bench/stiffmsa_bench --benchmark_filter='^6axis/public_solve/klu$' \\
        --benchmark_min_time=2
    bench/profile.py /tmp/chain.data -- taskset -c 0 build-bench/bench/stiffmsa_chain 100000 klu
    bench/profile.py /tmp/chain.data          # the shares of an existing recording again
"""
import argparse
import re
import subprocess
import sys

# (label, symbol regex). A stage's share is the largest inclusive share among the symbols it
# matches (overloads and clones nest, so they are not added up). Indented labels are parts of
# the stage above them.
STAGES = [
    ("stiffmsa::solve, whole", r"^stiffmsa::solve$"),
    ("load_model (YAML reading + validation)", r"^stiffmsa::load_model$"),
    ("  YAML parsing (libfyaml into the loader's tree)", r"^stiffmsa::detail::parse_yaml$"),
    ("  find_defects (validation)", r"^stiffmsa::find_defects$"),
    ("validate (model checks: load_model, Workspace, every solve)", r"^stiffmsa::validate$"),
    ("Workspace (validation, topology, pattern)", r"^stiffmsa::Workspace::Workspace"),
    ("  Assembler pattern (record + sort positions)", r"^stiffmsa::detail::Assembler::Assembler"),
    ("build_topology (every solve, also inside Workspace)", r"^stiffmsa::detail::build_topology$"),
    ("  ModelIndex (string hash maps; also in validate, equilibrium_error)", r"^stiffmsa::detail::ModelIndex::ModelIndex"),
    ("make_blocks", r"^stiffmsa::detail::make_blocks$"),
    ("  free_directions (also in fill_state_results)", r"^stiffmsa::detail::free_directions$"),
    ("Assembler::fill", r"^stiffmsa::detail::Assembler::fill$"),
    ("FactorizedSystem::factorize", r"^stiffmsa::detail::FactorizedSystem::factorize$"),
    ("  equilibrate", r"^stiffmsa::detail::equilibrate$"),
    ("  pattern analysis (ordering)", r"(EigenSparseLU|KluLU|UmfpackLU)::analyze$|analyzePattern|^klu_analyze$|"
                                      r"^umfpack_di_symbolic$"),
    ("  numeric LU", r"(EigenSparseLU|KluLU|UmfpackLU)::factorize$"),
    ("  condition estimate", r"detail::estimate_inverse_norm1$"),
    ("FactorizedSystem::solve (refined)", r"^stiffmsa::detail::FactorizedSystem::solve$"),
    ("  solve_once (scaling + triangular solves)", r"^stiffmsa::detail::FactorizedSystem::solve_once$"),
    ("  relative_residual", r"^stiffmsa::detail::relative_residual$"),
    ("right-hand sides (loads, unit wrenches)", r"Problem::(unit_wrench_rhs|load_rhs)$"),
    ("results: fill_state_results", r"fill_state_results$"),
    ("results: cartesian_stiffness (K = C⁻¹ and its checks)", r"^stiffmsa::detail::cartesian_stiffness$"),
    ("results: empty_result", r"empty_result$"),
    ("results: equilibrium_error", r"equilibrium_error$"),
    ("result file + summary (CLI)", r"^stiffmsa::(write_result_file|cli::print_solve_summary)"),
    ("kernel: page faults", r"^asm_exc_page_fault$"),
]
# Self time of the allocator, added up over its symbols.
HEAP = r"^(malloc|free|cfree.*|_int_malloc|_int_free|_int_realloc|realloc|calloc|malloc_consolidate|" \
       r"unlink_chunk.*|__libc_malloc.*|__libc_free.*|operator new.*|operator delete.*|" \
       r"__GI___libc_(malloc|free).*)$"


def report(data):
    out = subprocess.run(["perf", "report", "-i", data, "--children", "--sort", "symbol", "-g", "none",
                          "--stdio"], capture_output=True, text=True, check=True).stdout
    rows = []
    for line in out.splitlines():
        line = re.sub(r"(\s+-)+\s*$", "", line)  # empty columns at the end of the line
        m = re.match(r"^\s+([\d.]+)%\s+([\d.]+)%\s+\[[.k]\]\s+(.*?)\s*$", line)
        if m:
            rows.append((float(m.group(1)), float(m.group(2)), m.group(3)))
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--freq", default="2000", help="sampling frequency (default 2000 Hz)")
    parser.add_argument("--root", help="regex of the symbol whose samples are 100%% (default: all samples)")
    parser.add_argument("data", help="perf data file to write")
    parser.add_argument("command", nargs=argparse.REMAINDER)
    args = parser.parse_args()
    command = args.command[1:] if args.command[:1] == ["--"] else args.command
    if command:
        subprocess.run(["perf", "record", "-q", "-F", args.freq, "--call-graph", "dwarf,16384", "-o", args.data, "--"]
                       + command, check=True, stdout=sys.stderr)
    rows = report(args.data)
    root = max((c for c, _, s in rows if re.search(args.root, s)), default=100.0) if args.root else 100.0

    def share(pattern):
        return max((c for c, _, s in rows if re.search(pattern, s)), default=0.0)

    print(f"{'stage':<52} {'% of ' + ('root' if args.root else 'all'):>9}")
    for label, pattern in STAGES:
        value = share(pattern)
        if value >= 0.05:
            print(f"{label:<52} {100 * value / root:9.1f}")
    heap = sum(s for _, s, name in rows if re.search(HEAP, name))
    print(f"{'heap: malloc/free/new/delete (self time)':<52} {100 * heap / root:9.1f}")


if __name__ == "__main__":
    main()
