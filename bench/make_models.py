#!/usr/bin/env python3
"""Writes the benchmark's large models as stiffmsa/1 YAML files, the same models that
bench_models.cpp builds in code, for timing the `stiffmsa solve` command on them.

    make_models.py chain N             > chain.yaml   # N beam links, 10 m cantilever
    make_models.py frame NX NY STOREYS > frame.yaml   # building frame (5 5 10: 960 beams)
"""
import sys


def chain(n):
    out = ["format: stiffmsa/1", f"name: chain-{n}", "",
           "materials:", "  steel: {E: 2.1e11, G: 8.0e10}",
           "sections:", "  tube: {shape: tube, D: 0.1, t: 0.005}", "", "points:"]
    out += [f"  P{i}: [{10.0 * i / n!r}, 0, 0]" for i in range(n + 1)]
    out.append("links:")
    out += [f"  L{i}: {{type: beam, from: P{i - 1}, to: P{i}, material: steel, section: tube}}"
            for i in range(1, n + 1)]
    out += ["supports:", "  clamp: {type: rigid, at: P0}",
            "loads:", f"  - {{at: P{n}, wrench: [0, -100, 0, 0, 0, 0]}}",
            "end_effectors:", f"  tip: {{at: P{n}}}"]
    return out


def frame(nx, ny, storeys):
    def node(i, j, k):
        return f"n{i}_{j}_{k}"

    out = ["format: stiffmsa/1", f"name: frame-{nx}x{ny}x{storeys}", "",
           "materials:", "  steel: {E: 2.1e11, nu: 0.3}",
           "sections:", "  column: {shape: rect_tube, b: 0.3, h: 0.3, t: 0.012}",
           "  girder: {shape: rect_tube, b: 0.2, h: 0.35, t: 0.01}", "", "points:"]
    out += [f"  {node(i, j, k)}: [{4.0 * i!r}, {4.0 * j!r}, {3.5 * k!r}]"
            for k in range(storeys + 1) for j in range(ny + 1) for i in range(nx + 1)]
    out.append("links:")
    for k in range(1, storeys + 1):
        out += [f"  c{node(i, j, k)}: {{type: beam, from: {node(i, j, k - 1)}, to: {node(i, j, k)}, "
                 "material: steel, section: column}" for j in range(ny + 1) for i in range(nx + 1)]
        out += [f"  x{node(i, j, k)}: {{type: beam, from: {node(i, j, k)}, to: {node(i + 1, j, k)}, "
                 "material: steel, section: girder}" for j in range(ny + 1) for i in range(nx)]
        out += [f"  y{node(i, j, k)}: {{type: beam, from: {node(i, j, k)}, to: {node(i, j + 1, k)}, "
                 "material: steel, section: girder}" for j in range(ny) for i in range(nx + 1)]
    out.append("supports:")
    out += [f"  g{node(i, j, 0)}: {{type: rigid, at: {node(i, j, 0)}}}"
            for j in range(ny + 1) for i in range(nx + 1)]
    corner = node(nx, ny, storeys)
    out += ["loads:", f"  - {{at: {corner}, link: c{corner}, wrench: [20.0e3, 10.0e3, 0, 0, 0, 0]}}",
            "end_effectors:", f"  roof_corner: {{at: {corner}, link: c{corner}}}"]
    return out


def main(argv):
    if len(argv) == 3 and argv[1] == "chain":
        lines = chain(int(argv[2]))
    elif len(argv) == 5 and argv[1] == "frame":
        lines = frame(*(int(a) for a in argv[2:]))
    else:
        sys.exit(__doc__)
    sys.stdout.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv)
