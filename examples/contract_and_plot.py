"""Contracts a mesh to 70 % of its volume, saves every 10th frame as OFF and plots V/V0.

    /usr/bin/python3 examples/contract_and_plot.py INPUT.off OUT_FOLDER [FRAMES]

Needs the built module on PYTHONPATH (PYTHONPATH=build/python) and matplotlib.
"""
import pathlib
import sys

import matplotlib

matplotlib.use("Agg")  # files only, no display needed
import matplotlib.pyplot as plt

import shellcontract


def main(source, out_dir, frames=60):
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    vertices, faces = shellcontract.read_mesh(source)

    def save_every_10th(frame, v, metrics):
        if frame % 10 == 0:
            shellcontract.write_mesh(out_dir / "frame_{:04d}.off".format(frame), v, faces)

    result = shellcontract.contract(vertices, faces, frames=frames, target_volume=0.7, target_ramp=30,
                                    callback=save_every_10th)
    print(result)

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(result.log["frame"], result.log["volume_ratio"])
    ax.axhline(0.7, linestyle="--", color="grey", label="target")
    ax.set_xlabel("frame")
    ax.set_ylabel("V / V0")
    ax.legend()
    fig.savefig(out_dir / "volume_ratio.png", dpi=100)
    return 0 if result.status == "ok" else 1


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1], sys.argv[2], int(sys.argv[3]) if len(sys.argv) > 3 else 60))
