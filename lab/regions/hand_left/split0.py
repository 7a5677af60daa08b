# Region 0 of the hand's finder list cut in two by nearest labelled fingertip (3 or 4) point;
# writes the other regions unchanged, then the two halves. Usage: split0.py AUTO OUT
import sys
sys.path.insert(0, "/work/main/lab/regions")
import numpy as np, common, labels
rest, faces = common.read_off(common.mesh_path("hand"))
regs = common.read_face_list(sys.argv[1])
cent = common.face_centroids(rest, faces)
pts = {n: p for n, p, r in labels.parts_of("hand", rest)}
r0 = np.array(regs[0])
d3 = np.linalg.norm(cent[r0] - pts["fingertip 3"], axis=1)
d4 = np.linalg.norm(cent[r0] - pts["fingertip 4"], axis=1)
a, b = r0[d3 <= d4], r0[d3 > d4]
out = regs[1:] + [a.tolist(), b.tolist()]
open(sys.argv[2], "w").write("".join(" ".join(map(str, r)) + "\n" for r in out))
print("halves", len(a), len(b))
