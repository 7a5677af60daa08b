#!/usr/bin/python3
"""The elk seen from below and from the side with labels.py's four ball feet coloured (red, green,
blue, orange for feet 1-4): the check behind the feet's written points. Writes
lab/regions/elk_feet.png.

Usage: /usr/bin/python3 lab/regions/render_elk_feet.py
"""
import os
import sys

import matplotlib
import numpy as np

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import common  # noqa: E402
import labels  # noqa: E402

COLOURS = {"ball foot 1": [1, 0, 0, 1], "ball foot 2": [0, 0.7, 0, 1], "ball foot 3": [0, 0, 1, 1],
           "ball foot 4": [1, 0.6, 0, 1]}


def main():
    v, f = common.read_off(common.mesh_path("elk"))
    c = common.face_centroids(v, f)
    colour = np.tile([0.8, 0.8, 0.8, 1.0], (len(f), 1))
    for name, p, r in labels.parts_of("elk", v):
        if name in COLOURS:
            colour[np.linalg.norm(c - p, axis=1) < r] = COLOURS[name]
    fig = plt.figure(figsize=(12, 6))
    w = v[:, [0, 2, 1]]  # y up
    for i, (elev, azim) in enumerate([(-60, -60), (10, -120)]):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection(w[f], facecolors=colour, edgecolors="none"))
        for d, setter in enumerate([ax.set_xlim, ax.set_ylim, ax.set_zlim]):
            setter(w[:, d].min(), w[:, d].max())
        ax.view_init(elev=elev, azim=azim)
        ax.set_box_aspect(np.ptp(w, axis=0))
        ax.set_xlabel("x")
        ax.set_ylabel("z")
        ax.set_zlabel("y")
    plt.savefig(os.path.join(HERE, "elk_feet.png"), dpi=80)


if __name__ == "__main__":
    main()
