#!/usr/bin/python3
"""Renders a local contraction on regions picked by pointing (issue 55, items 3 and 5): the rest
mesh and the result of `shellcontract run MESH --regions FILE -p 0`, the regions coloured, side by
side in docs/images/regions_<name>_sink.png, and prints the sink / rest measures
(lab/regions/rest_motion.py).

Default: bear's two ear tips. With --parts the regions are the labelled parts of labels.py's
`parts_of` (sink.py's part_regions; --drop leaves some out) instead of --at points. Usage:
  /usr/bin/python3 lab/regions/render_sink.py [--build build] [--mesh bear]
      [--at 0.393,0.822,-0.056 --at -0.348,0.936,-0.051 | --parts [--drop head]] [--name bear_ears]
      [--azim 20]
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


COLOURS = [(230, 40, 40), (40, 90, 230), (140, 230, 40), (230, 170, 30), (170, 60, 200),
           (40, 200, 200), (230, 110, 170)]


def write_region_ply(path, v, f, regions):
    """An ASCII PLY as `regions` writes it (vertices first, then faces with an RGBA colour per
    region, grey outside), for the labelled parts, which the tool does not colour."""
    colour = [(160, 160, 160)] * len(f)
    for k, r in enumerate(regions):
        for j in r:
            colour[j] = COLOURS[k % len(COLOURS)]
    with open(path, "w") as fo:
        fo.write("ply\nformat ascii 1.0\nelement vertex %d\nproperty double x\nproperty double y\n"
                 "property double z\nelement face %d\nproperty list uchar int vertex_indices\n"
                 "property uchar red\nproperty uchar green\nproperty uchar blue\nproperty uchar alpha\n"
                 "end_header\n" % (len(v), len(f)))
        fo.write("".join("%.17g %.17g %.17g\n" % tuple(p) for p in v))
        fo.write("".join("3 %d %d %d %d %d %d 255\n" % (tuple(t) + c) for t, c in zip(f, colour)))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(common.ROOT, "build"))
    ap.add_argument("--mesh", default="bear")
    ap.add_argument("--at", action="append", default=None)
    ap.add_argument("--name", default="bear_ears")
    ap.add_argument("--azim", default="20")
    ap.add_argument("--parts", action="store_true", help="the labelled parts (labels.py), not --at")
    ap.add_argument("--drop", default="", help="with --parts: comma-separated part names to leave out")
    a = ap.parse_args()
    points = a.at or ["0.393,0.822,-0.056", "-0.348,0.936,-0.051"]
    exe = os.path.join(a.build, "shellcontract")
    mesh = common.mesh_path(a.mesh)
    out_dir = os.path.join(common.ROOT, "docs", "images")
    with tempfile.TemporaryDirectory() as tmp:
        ply, listed, out = (os.path.join(tmp, n) for n in ("r.ply", "r.txt", "out.off"))
        if a.parts:
            import sink  # noqa: E402 (its part_regions)
            rest, faces = common.read_off(mesh)
            regions = sink.part_regions(a.mesh, rest, faces, set(filter(None, a.drop.split(","))))
            with open(listed, "w") as fo:
                fo.write("".join(" ".join(map(str, r)) + "\n" for r in regions))
            write_region_ply(ply, rest, faces, regions)
        else:
            subprocess.run([exe, "regions", mesh, "-o", ply, "--face-list", listed] +
                           ["--region-at=" + p for p in points], check=True, stdout=subprocess.DEVNULL)
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
