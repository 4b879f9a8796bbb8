"""The picture at the top of the README: docs/pfem_skfem_results.png.

Two results at their ``--quick`` size: the plastic zone of the strip footing at
collapse (Tresca, thesis Sec 3.6: the Prandtl mechanism, Nc against 2 + pi) and a
granular column (a = 1, phi = 31 deg, thesis Sec 6.4.3) before and after it
collapses, particles coloured by their speed mid-run. Run from the repository root::

    python docs/make_readme_figure.py        # about a minute
"""
from pathlib import Path
import sys

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pfem_skfem import io, viz                                   # noqa: E402
from pfem_skfem.materials import Tresca                           # noqa: E402
from pfem_skfem.harness.figures import pyplot, save_figure  # noqa: E402
from pfem_skfem.harness.report import run_script  # noqa: E402
from verification import granular_column_plane, strip_footing     # noqa: E402

OUT = ROOT / "docs" / "pfem_skfem_results.png"


def main():
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(11, 3.6), layout="constrained",
                                      gridspec_kw={"width_ratios": [1, 1.7]})
    # the footing: yield ratio per element at the end of the Nc-settlement curve
    footing = run_script(strip_footing, "--quick", "--phi", "--no-figures")
    data = footing.data
    fine = max(data["models"])
    model = data["models"][fine]
    _, nc, hist = strip_footing.nc_curve(model, data["elastic"], Tresca(data["su"]), 0.06, 10,
                                         c=data["su"])
    disc = model["disc"]
    ratio = np.zeros(disc.mesh.nelements)
    np.maximum.at(ratio, disc.point_element, Tresca(data["su"]).yield_ratio(hist.sigma))
    points, cells = io.mesh_arrays(disc.mesh)
    viz.plot_field(left, points, cells, np.minimum(ratio, 1.0), cmap="magma",
                   label="yield ratio (1: plastic)")
    left.set_xlim(0, 3), left.set_ylim(-2, 0)
    left.set_xlabel("x [m]"), left.set_ylabel("y [m]")
    left.set_title(f"strip footing at collapse (Tresca)\nNc = {nc[-1]:.2f}, Prandtl 2 + pi = 5.14",
                   fontsize=10)
    # the column: the particles at t = 0 (grey) and at rest, coloured by speed at t = 1
    column = run_script(granular_column_plane, "--quick", "--no-figures", "--workers", "1")
    case = column.data["sweep"][0]
    frames = sorted(case["snapshots"])
    first, mid, last = (case["snapshots"][k] for k in (frames[0], frames[1], frames[-1]))
    right.scatter(*first["points"].T, s=6, color="0.8", label="t = 0")
    sc = right.scatter(*mid["points"].T, s=6, c=mid["speed"], cmap="viridis",
                       label="t / sqrt(h0/g) = 1")
    right.scatter(*last["points"].T, s=3, color="k", label="at rest")
    right.set_aspect("equal")
    right.set_xlabel("x / d0"), right.set_ylabel("y / d0")
    right.set_title("granular column collapse (PFEM), a = 1, phi = 31 deg\nat the start, "
                    "mid-run (colour: speed) and at rest", fontsize=10)
    right.legend(fontsize=7, loc="upper right")
    fig.colorbar(sc, ax=right, label="speed at t = 1 [m/s]", shrink=0.8)
    save_figure(fig, OUT, dpi=100)
    print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
