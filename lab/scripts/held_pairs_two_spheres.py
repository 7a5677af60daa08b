"""Two level-3 icospheres of radius 0.5, their facing poles 1e-4 apart (closer than the default
contact distance once normalized), as one OFF: the mesh of lab/pages/self-collision.md's section
"Pairs closer than delta at rest". Writes two.off in the current folder.

    /usr/bin/python3 lab/scripts/held_pairs_two_spheres.py
"""
import numpy as np
def ico(level):
    t=(1+5**.5)/2
    v=[[-1,t,0],[1,t,0],[-1,-t,0],[1,-t,0],[0,-1,t],[0,1,t],[0,-1,-t],[0,1,-t],[t,0,-1],[t,0,1],[-t,0,-1],[-t,0,1]]
    f=[[0,11,5],[0,5,1],[0,1,7],[0,7,10],[0,10,11],[1,5,9],[5,11,4],[11,10,2],[10,7,6],[7,1,8],[3,9,4],[3,4,2],[3,2,6],[3,6,8],[3,8,9],[4,9,5],[2,4,11],[6,2,10],[8,6,7],[9,8,1]]
    v=[list(np.array(p)/np.linalg.norm(p)) for p in v]
    for _ in range(level):
        mid={};nf=[]
        def m(a,b):
            k=(min(a,b),max(a,b))
            if k not in mid:
                p=np.array(v[a])+np.array(v[b]); v.append(list(p/np.linalg.norm(p))); mid[k]=len(v)-1
            return mid[k]
        for a,b,c in f:
            ab,bc,ca=m(a,b),m(b,c),m(c,a); nf+= [[a,ab,ca],[b,bc,ab],[c,ca,bc],[ab,bc,ca]]
        f=nf
    return np.array(v),np.array(f)
v,f=ico(3)
i=np.argmax(v[:,0]); a=v[i]
def rot_to_x(a):
    x=np.array([1.,0,0]); ax=np.cross(a,x); s=np.linalg.norm(ax); c=a@x
    if s<1e-12: return np.eye(3)
    ax/=s; K=np.array([[0,-ax[2],ax[1]],[ax[2],0,-ax[0]],[-ax[1],ax[0],0]])
    return np.eye(3)+s*K+(1-c)*K@K
R=rot_to_x(a); v=v@R.T
gap=1e-4
A=v*0.5; B=v*0.5; B[:,0]*=-1; B[:,0]+=1+gap
FB=f[:,[0,2,1]]
V=np.vstack([A,B]); F=np.vstack([f,FB+len(A)])
with open('two.off','w') as o:
    o.write("OFF\n%d %d 0\n"%(len(V),len(F)))
    for p in V: o.write("%.17g %.17g %.17g\n"%tuple(p))
    for t in F: o.write("3 %d %d %d\n"%tuple(t))
print(len(V), "pole A", np.argmax(A[:,0]), A[:,0].max(), "B min x", B[:,0].min())
