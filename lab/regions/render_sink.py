#!/usr/bin/python3
"""Renders a local contraction on regions picked by pointing (issue 55, items 3 and 5): the rest
mesh and the result of `shellcontract run MESH --regions FILE -p 0`, the regions coloured, side by
side in docs/images/regions_<name>_sink.png, and prints the sink / rest measures
(lab/regions/rest_motion.py).

Default: bear's two ear tips. Usage:
  /usr/bin/python3 lab/regions/render_sink.py [--build build] [--mesh bear]
      [--at 0.393,0.822,-0.056 --at -0.348,0.936,-0.051] [--name bear_ears] [--azim 20]
"""
import argparse
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402

RENDER = os.path.join(common.ROOT, "lab", "scripts", "render_ply.py")


def ply_with_positions(ply_in, ply_out, positions):
    """The regions PLY (ASCII, vertices first) with its vertex coordinates replaced."""
    lines = open(ply_in).read().split("\n")
    end = lines.index("end_header")
    for i, p in enumerate(positions):
        rest = lines[end + 1 + i].split()[3:]
        lines[end + 1 + i] = " ".join(["%.17g" % c for c in p] + rest)
    open(ply_out, "w").write("\n".join(lines))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--mesh", default="bear")
    ap.add_argument("--at", action="append", default=None)
    ap.add_argument("--name", default="bear_ears")
    ap.add_argument("--azim", default="20")
    a = ap.parse_args()
    points = a.at or ["0.393,0.822,-0.056", "-0.348,0.936,-0.051"]
    exe = os.path.join(a.build, "shellcontract")
    mesh = common.mesh_path(a.mesh)
    out_dir = os.path.join(common.ROOT, "docs", "images")
    with tempfile.TemporaryDirectory() as tmp:
        ply, listed, out = (os.path.join(tmp, n) for n in ("r.ply", "r.txt", "out.off"))
        subprocess.run([exe, "regions", mesh, "-o", ply, "--face-list", listed] + ["--region-at=" + p for p in points],
                       check=True, stdout=subprocess.DEVNULL)
        subprocess.run([exe, "run", mesh, "--regions", listed, "-p", "0", "-o", out, "-q", "--validate", "end"],
                       check=True)
        after = os.path.join(tmp, "after.ply")
        ply_with_positions(ply, after, common.read_off(out)[0])
        pngs = []
        for label, src in (("rest", ply), ("run -p 0", after)):
            png = os.path.join(tmp, label.replace(" ", "_") + ".png")
            subprocess.run([sys.executable, RENDER, src, png, "--size", "480x480", "--azim", a.azim,
                            "--title", f"{a.mesh}: {label}"], check=True, stdout=subprocess.DEVNULL)
            pngs.append(png)
        import matplotlib.image as mpimg
        import numpy as np
        images = [mpimg.imread(p) for p in pngs]
        h = min(i.shape[0] for i in images)
        target = os.path.join(out_dir, f"regions_{a.name}_sink.png")
        mpimg.imsave(target, np.concatenate([i[:h] for i in images], axis=1))
        print("wrote", target)
        subprocess.run([sys.executable, os.path.join(os.path.dirname(os.path.abspath(__file__)), "rest_motion.py"),
                        mesh, out, listed], check=True)


if __name__ == "__main__":
    main()
