#!/usr/bin/env python3
"""Writes the benchmark's large models as stiffmsa/1 YAML files, the same models that
bench_models.cpp builds in code, for timing the `stiffmsa solve` command on them.

    make_models.py chain N                > chain.yaml   # N beam links, 10 m cantilever
    make_models.py frame NX NY STOREYS    > frame.yaml   # building frame (5 5 10: 960 beams)
    make_models.py lattice NX NY NZ       > lattice.yaml # cubic lattice (6 6 7: 1 015 beams)
    make_models.py frame3dd NX NY STOREYS > frame.3dd    # the same frame as Frame3DD input
    make_models.py frame3dd NX NY STOREYS mm > frame.3dd # the same, in N and mm

The frame3dd mode writes the frame of the frame mode, node for node and beam for beam in the
same order, in Frame3DD's .3dd input format (Frame3DD's manual, "Input Data Format"), for
bench/frame3dd_compare.py. Frame3DD reads numbers only, so the section properties are computed
here by the formulas stiffmsa uses for a rect_tube (docs/model-format.md, shared/spec/sections.md).
Options, chosen so that Frame3DD does its ordinary linear static analysis and no more: shear 0
(Euler-Bernoulli, as stiffmsa's beams without `shear: true`; Asy and Asz are then unused and are
given stiffmsa's rect_tube defaults), geometric stiffness 0, one load case without gravity,
dx = -1 (no internal-force diagrams along the elements), and 0 dynamic modes, after which
Frame3DD reads no further (so no mass data and no matrix condensation).
Section orientation: Frame3DD's local axes with roll 0 ("Z-axis vertical") are stiffmsa's
default ones for the girders (a beam along X: y = +Y, z = +Z; along Y: y = -X, z = +Z), so a
girder's h (local z) is vertical in both. For a column Frame3DD's roll-0 axes are y = +Y,
z = -X, stiffmsa's (zref = X) y = -Y, z = +X: a roll of 180 degrees, which changes no element
stiffness in global axes, and the column section is square besides; roll 0 is written, exact
where a float 180 degrees would not be.
With `mm` the file is in N, mm and MPa (tonne/mm^3) instead of N, m and Pa: Frame3DD prints its
displacements with six decimals (.out), or seven significant digits in the m-file it writes for
a *.fmm input but any below 1e-8 of its length unit as 0, so bench/frame3dd_compare.py reads the
displacements from a run in mm and times the SI file.
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


def lattice(nx, ny, nz):
    """A cubic lattice of NX x NY x NZ cells: (NX+1)(NY+1)(NZ+1) nodes 1 m apart, a beam along
    every cell edge (the bottom layer's too), every bottom node clamped, a load at a top corner."""
    def node(i, j, k):
        return f"n{i}_{j}_{k}"

    out = ["format: stiffmsa/1", f"name: lattice-{nx}x{ny}x{nz}", "",
           "materials:", "  steel: {E: 2.1e11, nu: 0.3}",
           "sections:", "  tube: {shape: tube, D: 0.06, t: 0.004}", "", "points:"]
    out += [f"  {node(i, j, k)}: [{float(i)!r}, {float(j)!r}, {float(k)!r}]"
            for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)]
    out.append("links:")
    for k in range(nz + 1):
        if k > 0:
            out += [f"  z{node(i, j, k)}: {{type: beam, from: {node(i, j, k - 1)}, to: {node(i, j, k)}, "
                     "material: steel, section: tube}" for j in range(ny + 1) for i in range(nx + 1)]
        out += [f"  x{node(i, j, k)}: {{type: beam, from: {node(i, j, k)}, to: {node(i + 1, j, k)}, "
                 "material: steel, section: tube}" for j in range(ny + 1) for i in range(nx)]
        out += [f"  y{node(i, j, k)}: {{type: beam, from: {node(i, j, k)}, to: {node(i, j + 1, k)}, "
                 "material: steel, section: tube}" for j in range(ny) for i in range(nx + 1)]
    out.append("supports:")
    out += [f"  g{node(i, j, 0)}: {{type: rigid, at: {node(i, j, 0)}}}"
            for j in range(ny + 1) for i in range(nx + 1)]
    corner = node(nx, ny, nz)
    out += ["loads:", f"  - {{at: {corner}, link: z{corner}, wrench: [2.0e3, 1.0e3, -5.0e3, 0, 0, 0]}}",
            "end_effectors:", f"  top_corner: {{at: {corner}, link: z{corner}}}"]
    return out


def rect_tube(b, h, t):
    """A, Iy, Iz, J, Asy, Asz of stiffmsa's rect_tube (b along local y, h along local z)."""
    bi, hi = b - 2 * t, h - 2 * t
    return (b * h - bi * hi, (b * h ** 3 - bi * hi ** 3) / 12, (h * b ** 3 - hi * bi ** 3) / 12,
            2 * t * (b - t) ** 2 * (h - t) ** 2 / (b + h - 2 * t), 2 * t * b, 2 * t * h)


def frame3dd(nx, ny, storeys, mm=False):
    """The frame of frame(nx, ny, storeys) as a Frame3DD .3dd file (N, m, Pa or N, mm, MPa)."""
    s = 1000.0 if mm else 1.0  # length unit per metre
    E, nu, density = 2.1e11 / s ** 2, 0.3, 7850.0 / s ** 4  # density: Frame3DD needs d > 0 only
    G = E / (2 * (1 + nu))
    column, girder = rect_tube(0.3 * s, 0.3 * s, 0.012 * s), rect_tube(0.2 * s, 0.35 * s, 0.01 * s)
    units = "N mm MPa" if mm else "N m Pa"

    def node(i, j, k):  # Frame3DD numbers nodes from 1, in the order of frame()'s points
        return 1 + i + (nx + 1) * (j + (ny + 1) * k)

    beams = []
    for k in range(1, storeys + 1):
        beams += [(node(i, j, k - 1), node(i, j, k), column)
                  for j in range(ny + 1) for i in range(nx + 1)]
        beams += [(node(i, j, k), node(i + 1, j, k), girder)
                  for j in range(ny + 1) for i in range(nx)]
        beams += [(node(i, j, k), node(i, j + 1, k), girder)
                  for j in range(ny) for i in range(nx + 1)]
    nodes = [(4.0 * s * i, 4.0 * s * j, 3.5 * s * k)
             for k in range(storeys + 1) for j in range(ny + 1) for i in range(nx + 1)]
    out = [f"frame-{nx}x{ny}x{storeys}: stiffmsa bench frame (make_models.py frame3dd), {units}",
           "",
           f"{len(nodes)}  # number of nodes",
           "#  node  x  y  z  r (rigid radius)"]
    out += [f"{n} {x!r} {y!r} {z!r} 0" for n, (x, y, z) in enumerate(nodes, 1)]
    out += ["", f"{(nx + 1) * (ny + 1)}  # number of nodes with reactions",
            "#  node  x y z xx yy zz  (1: fixed)"]
    out += [f"{node(i, j, 0)} 1 1 1 1 1 1" for j in range(ny + 1) for i in range(nx + 1)]
    out += ["", f"{len(beams)}  # number of frame elements",
            "#  elmnt n1 n2  Ax Asy Asz  Jxx Iyy Izz  E G  roll density"]
    for m, (n1, n2, (A, Iy, Iz, J, Asy, Asz)) in enumerate(beams, 1):
        out.append(f"{m} {n1} {n2} {A!r} {Asy!r} {Asz!r} {J!r} {Iy!r} {Iz!r} {E!r} {G!r} 0 "
                   f"{density!r}")
    out += ["", "0  # 1: include shear deformation (0: Euler-Bernoulli, as stiffmsa)",
            "0  # 1: include geometric stiffness",
            "10.0  # exaggerate static mesh deformations",
            "-1  # x-axis increment for internal forces (-1: none)",
            "", "1  # number of static load cases",
            "0 0 0  # gravitational acceleration X Y Z (no self-weight)",
            "1  # number of loaded nodes",
            "#  node  Fx Fy Fz Mxx Myy Mzz",
            f"{node(nx, ny, storeys)} 20000.0 10000.0 0 0 0 0",
            "0  # number of uniform distributed loads",
            "0  # number of trapezoidal loads",
            "0  # number of internal concentrated loads",
            "0  # number of temperature loads",
            "0  # number of prescribed displacements",
            "", "0  # number of dynamic modes (0: Frame3DD reads no further)"]
    return out


def main(argv):
    if len(argv) == 3 and argv[1] == "chain":
        lines = chain(int(argv[2]))
    elif len(argv) == 5 and argv[1] == "frame":
        lines = frame(*(int(a) for a in argv[2:]))
    elif len(argv) == 5 and argv[1] == "lattice":
        lines = lattice(*(int(a) for a in argv[2:]))
    elif len(argv) in (5, 6) and argv[1] == "frame3dd" and argv[5:] in ([], ["mm"]):
        lines = frame3dd(*(int(a) for a in argv[2:5]), mm=len(argv) == 6)
    else:
        sys.exit(__doc__)
    sys.stdout.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv)
