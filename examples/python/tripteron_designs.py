"""Two designs of the Tripteron (examples/tripteron-parametric.yaml) compared in one plot: equal
links (L1 = L2 = 0.25 m) against a longer proximal link (L1 = 0.30 m, L2 = 0.22 m), the
platform's smallest translational stiffness as it moves along x.

    .venv/bin/python examples/python/tripteron_designs.py [OUT.png]
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")  # files only; no window
import matplotlib.pyplot as plt

import stiffmsa

MODEL = Path(__file__).resolve().parents[1] / "tripteron-parametric.yaml"
DESIGNS = {"equal links, L1 = L2 = 0.25 m": {"L1": 0.25, "L2": 0.25},
           "long proximal link, L1 = 0.30 m, L2 = 0.22 m": {"L1": 0.30, "L2": 0.22}}


def main(out="tripteron-designs.png"):
    figure, axes = plt.subplots(figsize=(7, 4.5), constrained_layout=True)
    for label, lengths in DESIGNS.items():
        rows = stiffmsa.load_family(MODEL, **lengths).sweep(grid={"px": (0.05, 0.45, 81)})
        k = rows.columns["platform.k_trans_min"]
        axes.semilogy(rows.columns["px"], k, label=label)
        worst = rows.worst["platform.k_trans_min"]
        print(f"{label}: {int((rows.status == 'ok').sum())} of {len(rows)} poses reachable, softest "
              f"{worst['value']:.4g} N/m at px = {worst['parameters']['px']:.3f} m")
    axes.set_xlabel("platform px [m] (py = 0.28 m, pz = 0.30 m)")
    axes.set_ylabel("platform.k_trans_min [N/m]")
    axes.set_title("Tripteron: two designs of the legs")
    axes.grid(True, which="both", alpha=0.3)
    axes.legend()
    figure.savefig(out, dpi=110)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:])
