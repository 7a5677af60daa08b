"""Shared parts of lab/scripts/paper_figures.py and its figure modules (figures_membrane.py,
figures_regions.py): loading meshes, drawing panels, the number formats of the page (the runs:
figure_sweep.py)."""
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import render_mesh as rm  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
PAPER_MESHES = ["eight", "hand", "elk", "bear"]
MATERIALS = ["stvk", "corotated", "linear", "mooney-rivlin"]
ENERGIES = ["arap", "sqrt", "stvk"]
K_B = [1.0, 0.1, 0.01, 0.001, 0.0]
REGION_TINT = np.array([0.95, 0.45, 0.35])


def load(path):
    V, F, _ = rm.read_mesh(path)
    return V, F


def mesh_path(name):
    return os.path.join(ROOT, "meshes" if name == "bumpy_sphere" else "data/meshes", name + ".off")


# ----------------------------------------------------------------------------- drawing helpers

def panel_grid(panels, path, title, rows, cols, size=(800, 600)):
    """panels: list of (image or None, caption). One PNG of about `size` pixels."""
    fig, axs = plt.subplots(rows, cols, figsize=(size[0] / 100, size[1] / 100), dpi=100)
    for ax in np.ravel(axs):
        ax.set_axis_off()
    for ax, (img, caption) in zip(np.ravel(axs), panels):
        if img is not None:
            ax.imshow(img)
        ax.set_title(caption, fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)


def draw(V, F, up, fit, colours=None, cols=3, rows=2, **kw):
    """One panel's render, sized for a rows×cols grid of an 800×600 figure."""
    # Shorter than a grid cell: room for the two-line captions.
    return rm.render(V, F, colours, up=up, fit=fit, size=(800 // cols, 500 // rows), **kw)


def fmt(x, digits=4):
    return "-" if x is None else f"{x:.{digits}f}"


def span(values):
    """'0.99' or '0.99-1.08': the range of some ratios, as printed."""
    lo, hi = (f"{v:.2f}" for v in (min(values, default=float("nan")),
                                   max(values, default=float("nan"))))
    return lo if lo == hi else f"{lo}-{hi}"


def pct(x):
    return f"{100 * x:.2f} %"


def measure_regions_check(r, name, mesh, args, region_args=()):
    """Does `--measure-regions` (documented as selecting the regions only to report their sink)
    change the run? Runs `args` with no region option, then with `region_args` and
    --measure-regions, then with --region-shrink 0 added. Returns (changes,
    region_pressure_acts, sentence)."""
    plain = r.run(f"{name}_plain", mesh, *args)["summary"]["final_volume_ratio"]
    measured = r.run(f"{name}_measured", mesh, *args, *region_args,
                     "--measure-regions")["summary"]["final_volume_ratio"]
    zero = r.run(f"{name}_measured_p0", mesh, *args, *region_args, "--measure-regions",
                 "--region-shrink", 0)["summary"]["final_volume_ratio"]
    changes = abs(measured - plain) > 1e-9
    acts = changes and abs(zero - plain) <= 1e-9
    shown = " ".join(os.path.basename(str(w)) for w in (*args, *region_args))
    text = (f"Check on {os.path.basename(mesh)} (`{shown}`): V/V0 {plain:.6f} with no region "
            f"option, {measured:.6f} with `--measure-regions`, {zero:.6f} with `--measure-regions "
            f"--region-shrink 0`. ")
    if acts:
        text += ("So with `--regions` given, the regions are contracted (the local "
                 "contraction's region pressure) and `--measure-regions` only adds the report, as "
                 "its `--help` says; `--measure-regions` alone measures without contracting.")
    elif changes:
        text += "So `--measure-regions` changes the run, and not through the region pressure."
    else:
        text += "So `--measure-regions` only measures, as documented."
    return changes, acts, text
