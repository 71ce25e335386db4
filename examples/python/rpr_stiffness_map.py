"""A stiffness map of the planar 3-RPR robot (examples/planar-3rpr-parametric.yaml): the
platform's smallest translational stiffness over a grid of positions, swept in C++ threads and
drawn with matplotlib.

    .venv/bin/python examples/python/rpr_stiffness_map.py [OUT.png]
"""

import sys

import matplotlib

matplotlib.use("Agg")  # files only; no window
import matplotlib.pyplot as plt
import numpy as np
from matplotlib.colors import LogNorm

import stiffmsa
from pathlib import Path

MODEL = Path(__file__).resolve().parents[1] / "planar-3rpr-parametric.yaml"


def main(out="rpr-stiffness-map.png"):
    family = stiffmsa.load_family(MODEL)
    grid = {"x": (0.1, 0.9, 81), "y": (0.05, 0.8, 76)}
    rows = family.sweep(grid=grid)
    nx, ny = grid["x"][2], grid["y"][2]
    # The first grid parameter varies fastest: rows of the CSV fill the map line by line in y.
    k = rows.columns["platform.k_trans_min"].reshape(ny, nx)
    x = rows.columns["x"][:nx]
    y = rows.columns["y"][::nx]

    figure, axes = plt.subplots(figsize=(7, 5.5), constrained_layout=True)
    axes.set_facecolor("0.8")  # failed poses (NaN) show the background
    mesh = axes.pcolormesh(x, y, np.ma.masked_invalid(k), norm=LogNorm(), cmap="viridis", shading="nearest")
    figure.colorbar(mesh, ax=axes, label="platform.k_trans_min [N/m]")
    worst = rows.worst["platform.k_trans_min"]
    if worst is not None:
        at = worst["parameters"]
        axes.plot(at["x"], at["y"], "rx", markersize=10, mew=2)
        # Labelled towards the middle of the map, so that the label stays inside it.
        towards_x = 1 if at["x"] < sum(grid["x"][:2]) / 2 else -1
        towards_y = 1 if at["y"] < sum(grid["y"][:2]) / 2 else -1
        axes.annotate(f"softest: {worst['value']:.3g} N/m", (at["x"], at["y"]), textcoords="offset points",
                      xytext=(10 * towards_x, 10 * towards_y), ha="left" if towards_x > 0 else "right",
                      va="bottom" if towards_y > 0 else "top", color="red",
                      bbox={"boxstyle": "round", "facecolor": "white", "alpha": 0.8, "edgecolor": "none"})
    axes.set_xlabel("platform x [m]")
    axes.set_ylabel("platform y [m]")
    failed = int(np.count_nonzero(rows.status != "ok"))
    axes.set_title(f"{rows.model}: smallest translational stiffness\n"
                   f"{len(rows)} poses ({failed} failed, grey), phi = {family.defaults['phi']} rad")
    axes.set_aspect("equal")
    figure.savefig(out, dpi=110)
    print(f"{len(rows)} poses in {rows.seconds:.3f} s on {rows.threads} threads; wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:])
