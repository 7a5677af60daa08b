#!/usr/bin/python3
"""Regenerates the paper's Figs. 13, 16-18, 19 and 20 (Sun et al., J. Software 2020, section 6)
with the `shellcontract` CLI: runs the simulations, measures them, and writes PNGs and
lab/figures/README.md, where each figure's numbers stand beside the paper's claim.

Needs Debian's python3 with numpy and matplotlib (/usr/bin/python3) and the paper's meshes in
data/meshes (scripts/fetch_paper_meshes.sh). Every number in the README comes from the runs of
this invocation; nothing is typed in by hand.

The runs go through the sweep engine (`python3 -m shellcontract.sweep`, an embedded Dask
cluster with a worker per core; lab/scripts/figure_sweep.py), so they use every core and a
killed invocation loses no finished run.

Usage: /usr/bin/python3 lab/scripts/paper_figures.py [--tool build/shellcontract] [--out lab/figures]
                                                 [--quick] [--work DIR] [--workers N]
  --quick: 20 frames, no elk or bear: a smoke run of the whole pipeline (under a minute); write
           it somewhere other than lab/figures.
  --work DIR: keep the sweep's jobs in DIR; the next invocation with the same DIR skips every
           finished run (the sweep's job ids), e.g. for editing the text. The committed page
           comes from an invocation with an empty DIR.
"""
import argparse
import os
import shutil
import sys
import tempfile
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from figure_common import PAPER_MESHES, ROOT, mesh_path  # noqa: E402
from figure_sweep import SweepRunner  # noqa: E402
import figures_membrane  # noqa: E402
import figures_regions  # noqa: E402
from figures_membrane import fig13, fig16_18  # noqa: E402
from figures_regions import fig19, fig20  # noqa: E402

# ----------------------------------------------------------------------------- main

def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--tool", default=os.path.join(ROOT, "build", "shellcontract"))
    ap.add_argument("--out", default=os.path.join(ROOT, "lab", "figures"))
    ap.add_argument("--work", default=None, help="keep the runs' meshes, logs and summaries here")
    ap.add_argument("--quick", action="store_true", help="20 frames, no elk or bear (smoke run)")
    ap.add_argument("--workers", type=int, default=None,
                    help="the sweep's worker processes (default: one per core)")
    a = ap.parse_args()
    for m in PAPER_MESHES:
        if not os.path.exists(mesh_path(m)):
            sys.exit(f"{mesh_path(m)} is missing: run scripts/fetch_paper_meshes.sh")
    if a.quick:
        cfg = {"frames": 20, "meshes": ["eight", "hand", "bumpy_sphere"], "kb_mesh": "hand",
               "aniso_mesh": "bumpy_sphere", "render20": ["hand", "bumpy_sphere"]}
    else:
        cfg = {"frames": 100, "meshes": ["eight", "hand", "elk", "bear", "bumpy_sphere"],
               "kb_mesh": "hand", "aniso_mesh": "bumpy_sphere", "render20": ["bumpy_sphere", "bear"]}
    cfg.update({"aniso_pressure": 0, "fiber_target": 0.8})
    os.makedirs(a.out, exist_ok=True)
    work = a.work or tempfile.mkdtemp(prefix="paper_figures_")
    os.makedirs(work, exist_ok=True)
    r = SweepRunner(a.tool, work, a.workers)
    start = time.time()

    figures = [lambda out: fig13(r, cfg, out), lambda out: fig16_18(r, cfg, out),
               lambda out: fig19(r, cfg, out), lambda out: fig20(r, cfg, out),
               lambda out: r.run("defaults", mesh_path("eight"), "--frames", 1)]
    # The collecting passes render nothing (their results are stand-ins).
    no_render = {"draw": lambda *args, **kw: None, "panel_grid": lambda *args, **kw: None}
    *sections, defaults_run = r.draw_all(figures, a.out, {figures_membrane: no_render,
                                                          figures_regions: no_render})
    opts = defaults_run["summary"]["options"]
    keys = ["pressure", "damping", "k-b", "material", "solver", "bending", "iterations", "dt",
            "collisions", "inward", "region-shrink", "air-balance"]
    # An option without effect in that run (the local contraction's, with no regions) is recorded
    # empty: not a default to name.
    defaults = ", ".join(f"`--{k} {opts[k]}`" for k in keys if opts.get(k))
    elapsed = time.time() - start
    default_tool = os.path.join(ROOT, "build", "shellcontract")
    tool_arg = "" if os.path.abspath(a.tool) == default_tool else f" --tool {a.tool}"
    header = f"""# The paper's figures, regenerated

Sun et al., "Local anisotropic contraction deformation of thin shell" (J. Software 2020), section 6:
Figs. 13, 16-18, 19 and 20, re-run with `shellcontract` and measured. Every number below was
written by the command

```sh
/usr/bin/python3 lab/scripts/paper_figures.py{' --quick' if a.quick else ''}{tool_arg}
```

({r.count} runs through the sweep engine in {r.sweeps} sweeps, {elapsed / 60:.1f} min on the
machine that made this page; the runs' own wall times add up to {r.seconds / 60:.1f} min). The paper's claims are paraphrased or quoted (in
translation) from its text with their figure numbers; its own numbers are only in its bar charts
and curves, which are not reproduced here. Where ours differs, the text says so. The paper runs
100 frames; {'this quick run uses ' + str(cfg['frames']) if a.quick else 'so do we'}. Settings not
named in a figure are the CLI's defaults at the time of the run: {defaults}.

Renders: `lab/scripts/render_mesh.py` (a numpy z-buffer rasterizer, per-pixel depth test, flat
Lambert shading; the up axis from the mesh by the rule in `detect_up`). Each output is drawn at
its input's scale, so shrinking shows.
"""
    if r.not_ok:
        header += ("\n**Runs that did not end normally** (their last good state is used): "
                   + "; ".join(r.not_ok) + ".\n")
    with open(os.path.join(a.out, "README.md"), "w") as f:
        f.write(header + "\n" + "\n".join(sections))
    if a.work:
        print(f"runs kept in {work}")
    else:
        shutil.rmtree(work)
    print(f"wrote {a.out}/README.md and its PNGs in {elapsed:.0f} s ({r.count} runs)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
