#!/usr/bin/python3
"""Renders lab/regions/creases_hand.png: the hand's finder regions before and after the crease rule
(creases.md), region 0 red, from two face lists written by `shellcontract regions hand.off
--face-list FILE` with main's build and with this branch's.

Usage: /usr/bin/python3 lab/regions/creases_render.py BEFORE.txt AFTER.txt
"""
import sys, numpy as np
sys.path.insert(0,'lab/regions')
import common
import matplotlib; matplotlib.use('Agg')
import matplotlib.pyplot as plt
from mpl_toolkits.mplot3d.art3d import Poly3DCollection
v,f=common.read_off(common.mesh_path('hand'))[:2]; f=np.array(f)
cols_r=[[0.9,0.1,0.1,1],[0.1,0.3,0.9,1],[0.4,0.85,0.1,1],[0.9,0.6,0.1,1],[0,0.35,0.3,1]]
light=np.array([0.3,-0.3,1]); light/=np.linalg.norm(light)
n=np.cross(v[f[:,1]]-v[f[:,0]],v[f[:,2]]-v[f[:,0]]); n/=np.linalg.norm(n,axis=1)[:,None]
shade=0.45+0.55*np.clip(n@light,0,1)
fig=plt.figure(figsize=(12,6))
for k,(fn,title) in enumerate([(sys.argv[1],'before (main): region 0 red'),(sys.argv[2],'after (crease rule): region 0 red')]):
    regs=common.read_face_list(fn)
    c=np.tile([0.75,0.75,0.75,1.0],(len(f),1))
    for i,r in enumerate(regs): c[r]=cols_r[i]
    c[:,:3]*=shade[:,None]
    ax=fig.add_subplot(1,2,k+1,projection='3d')
    ax.add_collection3d(Poly3DCollection(v[f],facecolors=c,edgecolors='none'))
    lo,hi=v.min(0),v.max(0); m=(lo+hi)/2; h=(hi-lo).max()/2
    ax.set_xlim(m[0]-h,m[0]+h);ax.set_ylim(m[1]-h,m[1]+h);ax.set_zlim(m[2]-h,m[2]+h)
    ax.view_init(elev=65,azim=-80); ax.set_axis_off(); ax.set_title(title)
plt.tight_layout(); plt.savefig('lab/regions/creases_hand.png',dpi=80)
