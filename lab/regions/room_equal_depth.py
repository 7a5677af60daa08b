#!/usr/bin/python3
"""Issue 55 point 2: the room test (room.py: drop a region whose dimple keeps less than KEEP of
its mirror image's sink before meeting the shell) and equal-depth strengths (equal_depth.py:
s_i = (min m / m_i) ** P) together, then sink.py's measures and pass rule on the kept regions
(lab/regions/equal_depth.md, last section).

Usage: [KEEP=0.7] [P=0.5] /usr/bin/python3 lab/regions/room_equal_depth.py [MESHES] [OUT.md]
"""
import os, sys, subprocess, tempfile
import numpy as np
HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import common, sink_why
from room import incident_faces, region_room
KEEP = float(os.environ.get("KEEP", "0.7")); P = float(os.environ.get("P", "0.5"))
meshes = sys.argv[1].split(",") if len(sys.argv) > 1 else ["bear","hand","elk","kitten","bumpy_sphere"]
exe = os.path.join(common.ROOT, "build", "shellcontract")
keep = tempfile.mkdtemp(prefix="room_equal_depth.")
fls = []
for name, path, rest, faces, diag in common.each_mesh(meshes):
    regions, _, _ = common.auto_regions(exe, path, keep)
    normals = common.rest_normals(rest, faces)
    tri, incident = rest[faces], incident_faces(faces)
    kept_regions, m = [], []
    for ri, region in enumerate(regions):
        whole, kept = region_room(rest, faces, region, normals, diag, tri, incident)
        share = kept / whole if whole > 0 else 0
        mi = sink_why.geometry(rest, faces, region, normals, diag, 0.7)["mirror"]
        print(f"{name} region {ri}: share {share:.2f} mirror {mi:.4f}", flush=True)
        if share >= KEEP:
            kept_regions.append(region); m.append(mi)
    s = [min(1.0, (min(m) / x) ** P) if x > 0 else 1.0 for x in m]
    fl = os.path.join(keep, f"{name}.txt")
    with open(fl, "w") as f:
        f.write("".join(f"{si:.4f}: " + " ".join(map(str, r)) + "\n" for si, r in zip(s, kept_regions)))
    print(f"{name}: strengths", ", ".join(f"{x:.3f}" for x in s), flush=True)
    fls.append(f"{name}={fl}")
cmd = [sys.executable, os.path.join(HERE, "sink.py"), "--title", f"room {KEEP} + P {P}", "--out", sys.argv[2] if len(sys.argv) > 2 else os.path.join(keep, "sink.md")]
for fl in fls: cmd += ["--face-list", fl]
subprocess.run(cmd, check=True)
