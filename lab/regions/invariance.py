#!/usr/bin/python3
"""Issue 55 point 1's invariance, checked from outside: the automatic regions of each mesh against
those of the same mesh rotated (a random rotation), scaled by 3.7, moved, with its vertices and
faces in a random order and each face's corners rotated: prints whether the face sets (mapped back
to the original face ids) are the same.

Usage: /usr/bin/python3 lab/regions/invariance.py MESH...   (bear hand elk kitten eight bumpy_sphere)
"""
import os
import subprocess
import sys

import numpy as np
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import common  # noqa: E402
exe = os.path.join(common.ROOT, "build", "shellcontract")
rng=np.random.default_rng(7)
import tempfile  # noqa: E402
_tmp = tempfile.mkdtemp()
FL = os.path.join(_tmp, "fl.txt")
TMP_OFF = os.path.join(_tmp, "t.off")
def write_off(p,v,f):
    with open(p,"w") as o:
        o.write(f"OFF\n{len(v)} {len(f)} 0\n")
        for x in v: o.write("%.17g %.17g %.17g\n"%tuple(x))
        for t in f: o.write("3 %d %d %d\n"%tuple(t))
def regs(p):
    subprocess.run([exe,"regions",p,"--face-list",FL],check=True,capture_output=True)
    return common.read_face_list(FL)
for name in sys.argv[1:]:
    v,f=common.read_off(common.mesh_path(name))
    base=[frozenset(r) for r in regs(common.mesh_path(name))]
    q,_=np.linalg.qr(rng.normal(size=(3,3)));
    if np.linalg.det(q)<0: q[:,0]*=-1
    perm=rng.permutation(len(v)); inv=np.argsort(perm)
    fperm=rng.permutation(len(f))
    v2=(v@q.T)*3.7+np.array([5,-2,1.0]); v2=v2[perm]; f2=inv[f][fperm]
    # rotate each face's corners cyclically by a random amount
    s=rng.integers(0,3,len(f2)); f2=np.array([np.roll(t,-k) for t,k in zip(f2,s)])
    write_off(TMP_OFF,v2,f2)
    r2=[frozenset(int(fperm[i]) for i in r) for r in regs(TMP_OFF)]
    print(name, len(base), len(r2), "same sets" if set(base)==set(r2) else "DIFFERENT",
          [len(r) for r in base], [len(r) for r in r2])
