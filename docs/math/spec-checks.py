# Numerical checks for docs/math/spec.md (pure Python 3, no dependencies). Run: python3 docs/math/spec-checks.py
# Dependency-free numerical checks for the math spec (pure Python).
import math, random
random.seed(1)

def add(a,b): return [a[i]+b[i] for i in range(len(a))]
def sub(a,b): return [a[i]-b[i] for i in range(len(a))]
def mul(s,a): return [s*x for x in a]
def dot(a,b): return sum(a[i]*b[i] for i in range(len(a)))
def cross(a,b): return [a[1]*b[2]-a[2]*b[1], a[2]*b[0]-a[0]*b[2], a[0]*b[1]-a[1]*b[0]]
def norm(a): return math.sqrt(dot(a,a))
def normalize(a): n=norm(a); return [x/n for x in a]
def matmul(A,B):
    return [[sum(A[i][k]*B[k][j] for k in range(len(B))) for j in range(len(B[0]))] for i in range(len(A))]
def T(A): return [list(r) for r in zip(*A)]
def inv2(M):
    d=M[0][0]*M[1][1]-M[0][1]*M[1][0]
    return [[M[1][1]/d,-M[0][1]/d],[-M[1][0]/d,M[0][0]/d]]
def det2(M): return M[0][0]*M[1][1]-M[0][1]*M[1][0]
def madd(A,B,s=1.0): return [[A[i][j]+s*B[i][j] for j in range(len(A[0]))] for i in range(len(A))]
def mscale(s,A): return [[s*x for x in r] for r in A]
def tr(A): return sum(A[i][i] for i in range(len(A)))
def frob2(A): return sum(x*x for r in A for x in r)
I2=[[1.0,0.0],[0.0,1.0]]

def rest_frame(X1,X2,X3):
    E1=sub(X1,X3); E2=sub(X2,X3)
    N=normalize(cross(E1,E2)); T1=normalize(E1); T2=cross(N,T1)
    Dm=[[norm(E1), dot(E2,T1)],[0.0, dot(E2,T2)]]
    A=0.5*norm(cross(E1,E2))
    return Dm,A,N,T1,T2

def cur_frame(x1,x2,x3,nref):
    e1=sub(x1,x3); e2=sub(x2,x3)
    n=normalize(cross(e1,e2)); s=1.0 if dot(n,nref)>=0 else -1.0
    nu=mul(s,n); t1=normalize(e1); t2=cross(nu,t1)
    p=[t1,t2]
    Ds=[[e1[i],e2[i]] for i in range(3)]
    return p,Ds,s

def polar_so2(Fb):
    c=Fb[0][0]+Fb[1][1]; s=Fb[1][0]-Fb[0][1]; r=math.hypot(c,s)
    if r<1e-300: return I2, r
    return [[c/r,-s/r],[s/r,c/r]], r

a_dir=normalize([0.8,0.35])
A_mat=[[a_dir[0]*a_dir[0],a_dir[0]*a_dir[1]],[a_dir[1]*a_dir[0],a_dir[1]*a_dir[1]]]
mu,lam=1.3,2.1
C10,C01=0.7,0.25

def energy_P(model,Fb):
    if model=='stvk':
        C=matmul(T(Fb),Fb); E=mscale(0.5,madd(C,I2,-1))
        psi=mu*frob2(E)+0.5*lam*tr(E)**2
        P=matmul(Fb,madd(mscale(2*mu,E),mscale(lam*tr(E),I2)))
        return psi,P
    if model=='coro':
        R,_=polar_so2(Fb); S=matmul(T(R),Fb)
        psi=mu*frob2(madd(Fb,R,-1))+0.5*lam*(tr(S)-2)**2
        P=madd(mscale(2*mu,madd(Fb,R,-1)),mscale(lam*(tr(S)-2),R))
        return psi,P
    if model=='linear':
        eps=madd(mscale(0.5,madd(Fb,T(Fb))),I2,-1)
        psi=mu*frob2(eps)+0.5*lam*tr(eps)**2
        P=madd(mscale(mu,madd(madd(Fb,T(Fb)),I2,-2)),mscale(lam*(tr(Fb)-2),I2))
        return psi,P
    if model=='mr':
        C=matmul(T(Fb),Fb); J=det2(Fb); I1=tr(C); d=J*J
        psi=C10*(I1+1/d-3)+C01*(d+I1/d-3)
        cof=[[Fb[1][1],-Fb[1][0]],[-Fb[0][1],Fb[0][0]]]  # = J F^{-T}
        P=madd(madd(mscale(2*C10,Fb),mscale(-2*C10/J**3,cof)),
               madd(madd(mscale(2*C01*J,cof),mscale(2*C01/J**2,Fb)),mscale(-2*C01*I1/J**3,cof)))
        return psi,P
    Fa=[dot(Fb[0],a_dir),dot(Fb[1],a_dir)]; I5=dot(Fa,Fa)
    FA=matmul(Fb,A_mat)
    if model=='astvk':
        return 0.5*mu*(I5-1)**2, mscale(2*mu*(I5-1),FA)
    if model=='asqrt':
        return 0.5*mu*(math.sqrt(I5)-1)**2, mscale(mu*(1-1/math.sqrt(I5)),FA)
    if model=='aarap':
        J=det2(Fb); sg=1.0 if (I5+J)>=0 else -1.0   # sign(I4) = sign(I5 + det Fbar)
        return 0.5*mu*(math.sqrt(I5)-sg)**2, mscale(mu*(1-sg/math.sqrt(I5)),FA)
    raise ValueError

def tri_energy_grad(model,x,X,nref,p_frozen=None):
    Dm,Ar,N,_,_=rest_frame(*X)
    p,Ds,s=cur_frame(*x,nref)
    if p_frozen is not None: p=p_frozen
    F=matmul(Ds,inv2(Dm))             # 3x2
    Fb=matmul(p,F)                    # 2x2
    psi,Pb=energy_P(model,Fb)
    P3=matmul(T(p),Pb)                # 3x2 lift p^T Pbar
    G=mscale(Ar,matmul(P3,T(inv2(Dm))))
    g1=[G[i][0] for i in range(3)]; g2=[G[i][1] for i in range(3)]
    g3=mul(-1,add(g1,g2))
    return Ar*psi,[g1,g2,g3],p

def fd_grad(fun,x,h=1e-6):
    g=[]
    for v in range(len(x)):
        gv=[]
        for c in range(3):
            xp=[list(q) for q in x]; xm=[list(q) for q in x]
            xp[v][c]+=h; xm[v][c]-=h
            gv.append((fun(xp)-fun(xm))/(2*h))
        g.append(gv)
    return g

def relerr(g,gf):
    num=math.sqrt(sum((g[i][c]-gf[i][c])**2 for i in range(len(g)) for c in range(3)))
    den=max(1e-30,math.sqrt(sum(gf[i][c]**2 for i in range(len(g)) for c in range(3))))
    return num/den

def rand_rot():
    q=normalize([random.gauss(0,1) for _ in range(4)]); w,x,y,z=q
    return [[1-2*(y*y+z*z),2*(x*y-z*w),2*(x*z+y*w)],[2*(x*y+z*w),1-2*(x*x+z*z),2*(y*z-x*w)],[2*(x*z-y*w),2*(y*z+x*w),1-2*(x*x+y*y)]]
def apply(R,v): return [dot(R[i],v) for i in range(3)]

X=[[0.1,0.0,0.2],[1.1,0.2,0.1],[0.3,0.9,0.4]]
Dm,Ar,Nrest,_,_=rest_frame(*X)
x=[add(X[i],[random.uniform(-.15,.15) for _ in range(3)]) for i in range(3)]
print("== triangle energies: rest zero / FD / rotation invariance ==")
for model in ['stvk','coro','linear','mr','astvk','asqrt','aarap']:
    E0,g0,_=tri_energy_grad(model,X,X,Nrest)
    E,g,p=tri_energy_grad(model,x,X,Nrest)
    gf=fd_grad(lambda xx: tri_energy_grad(model,xx,X,Nrest)[0], x)
    e_fd=relerr(g,gf)
    gf_frozen=fd_grad(lambda xx: tri_energy_grad(model,xx,X,Nrest,p_frozen=p)[0], x)
    e_fz=relerr(g,gf_frozen)
    R=rand_rot(); t=[0.3,-1.2,2.0]
    xr=[add(apply(R,q),t) for q in x]
    Er,gr,_=tri_energy_grad(model,xr,X,apply(R,Nrest))
    rot_g=max(abs(gr[i][c]-apply(R,g[i])[c]) for i in range(3) for c in range(3))
    gsum=max(abs(sum(g[i][c] for i in range(3))) for c in range(3))
    # gradient lies in current plane?
    n=normalize(cross(sub(x[0],x[2]),sub(x[1],x[2])))
    outofplane=max(abs(dot(gi,n)) for gi in g)
    print(f"{model:7s} E_rest={E0:.2e} |g_rest|={max(norm(v) for v in g0):.2e} E={E:.5f} "
          f"FD_rel={e_fd:.1e} FD_frozen_p_rel={e_fz:.1e} dE_rot={abs(Er-E):.1e} dg_rot={rot_g:.1e} sum_g={gsum:.1e} g.n={outofplane:.1e}")

print("== I4 closed form vs polar ==")
for trial in range(5):
    Fb=[[random.uniform(-1.5,1.5) for _ in range(2)] for _ in range(2)]
    R,r=polar_so2(Fb); S=matmul(T(R),Fb)
    I4=dot(a_dir,[dot(S[0],a_dir),dot(S[1],a_dir)])
    Fa=[dot(Fb[0],a_dir),dot(Fb[1],a_dir)]; I5=dot(Fa,Fa); J=det2(Fb)
    C=matmul(T(Fb),Fb)
    print(f"det={J:+.3f} I4={I4:+.6f} (I5+J)/rho={(I5+J)/r:+.6f} rho2-(trC+2J)={r*r-(tr(C)+2*J):.1e} S_sym={S[0][1]-S[1][0]:.1e}")

# ---- part 2 ----
print("\n== inverted (s=-1) triangle, FD ==")
x=[add(X[i],[random.uniform(-.15,.15) for _ in range(3)]) for i in range(3)]
ncur=normalize(cross(sub(x[0],x[2]),sub(x[1],x[2])))
nref=mul(-1,ncur)
for model in ['stvk','coro','mr','astvk','asqrt','aarap']:
    E,g,p=tri_energy_grad(model,x,X,nref)
    Ep,_,_=tri_energy_grad(model,x,X,ncur)
    gf=fd_grad(lambda xx: tri_energy_grad(model,xx,X,nref)[0], x)
    print(f"{model:6s} E(s=-1)={E:.5f} E(s=+1)={Ep:.5f} FD_rel={relerr(g,gf):.1e}")

print("\n== Bergou/Bender isometric bending, paper labelling ==")
def cot_interior(apex,p,q):
    u=sub(p,apex); v=sub(q,apex)
    return dot(u,v)/norm(cross(u,v))
def bergou_K(x0,x1,x2,x3):
    c01=cot_interior(x1,x0,x2)  # e0,e1 share x1 (tri 1)
    c04=cot_interior(x1,x0,x3)  # e0,e4 share x1 (tri 2)
    c02=cot_interior(x0,x1,x2)  # e0,e2 share x0 (tri 1)
    c03=cot_interior(x0,x1,x3)  # e0,e3 share x0 (tri 2)
    K=[c01+c04, c02+c03, -c01-c02, -c03-c04]
    A0=0.5*norm(cross(sub(x1,x0),sub(x2,x0))); A1=0.5*norm(cross(sub(x1,x0),sub(x3,x0)))
    return K,A0,A1
# flat rest hinge
r0=[0,0,0]; r1=[1.3,0,0]; r2=[0.4,0.9,0]; r3=[0.7,-0.8,0]
K,A0,A1=bergou_K(r0,r1,r2,r3)
print("sum K =",sum(K))
c=3.0/(A0+A1)
def EB(xs): h=[sum(K[i]*xs[i][d] for i in range(4)) for d in range(3)]; return 0.5*c*dot(h,h)
def rotx(v,th): return [v[0], v[1]*math.cos(th)-v[2]*math.sin(th), v[1]*math.sin(th)+v[2]*math.cos(th)]
for th in [0.0,0.3,1.0,2.0,3.0]:
    xs=[r0,r1,r2,rotx(r3,th)]   # isometric fold of tri 2 about the shared edge (x-axis)
    print(f"theta={th:.2f} E_B={EB(xs):.6f} 6|e|^2 sin^2(th/2)/(A0+A1)={6*1.3**2*math.sin(th/2)**2/(A0+A1):.6f}")
xs=[r0,r1,add(r2,[0.05,-0.02,0.1]),rotx(r3,0.7)]
h=[sum(K[i]*xs[i][d] for i in range(4)) for d in range(3)]
g=[mul(c*K[i],h) for i in range(4)]
gf=fd_grad(EB,xs)
print("E_B grad FD rel:",f"{relerr(g,gf):.1e}")
# curved rest state: E_B(rest) != 0
cr=[r0,r1,r2,rotx(r3,0.5)]
K,A0,A1=bergou_K(*cr); c=3.0/(A0+A1)
print("curved rest hinge (bent 0.5 rad): E_B(rest) =",f"{EB(cr):.4f}", "(nonzero => flat-rest model)")

print("\n== dihedral angle gradient (Bridson 2003 form) ==")
def theta(xs):
    x0,x1,x2,x3=xs
    NA=cross(sub(x1,x0),sub(x2,x0)); NB=cross(sub(x0,x1),sub(x3,x1)); e=normalize(sub(x1,x0))
    nA=normalize(NA); nB=normalize(NB)
    return math.atan2(dot(cross(nA,nB),e), dot(nA,nB))
def dtheta(xs):
    x0,x1,x2,x3=xs
    NA=cross(sub(x1,x0),sub(x2,x0)); NB=cross(sub(x0,x1),sub(x3,x1)); ev=sub(x1,x0); L=norm(ev); eh=mul(1/L,ev)
    a=mul(1/dot(NA,NA),NA); b=mul(1/dot(NB,NB),NB)
    u2=mul(L,a); u3=mul(L,b)
    u0=add(mul(dot(sub(x2,x1),eh),a), mul(dot(sub(x3,x1),eh),b))
    u1=mul(-1,add(mul(dot(sub(x2,x0),eh),a), mul(dot(sub(x3,x0),eh),b)))
    return [u0,u1,u2,u3]
for th in [0.4,-0.9,2.5]:
    xs=[r0,r1,add(r2,[0.03,0.01,-0.05]),rotx(r3,th)]
    g=dtheta(xs); gf=fd_grad(theta,xs)
    gneg=[mul(-1,v) for v in g]
    print(f"fold={th:+.2f} theta={theta(xs):+.4f} rel(+u)={relerr(g,gf):.1e} rel(-u)={relerr(gneg,gf):.1e} sumu={max(abs(sum(v[d] for v in g)) for d in range(3)):.1e}")
# sign convention: convex (outward normals) fold
print("flat theta:",theta([r0,r1,r2,r3]))

print("\n== CCD cubic and DNF Bernstein coefficients ==")
def cubic_coeffs(p,a,b,c,dp,da,db,dc):
    # f(t) = ((b-a)+t(db-da)) x ((c-a)+t(dc-da)) . ((p-a)+t(dp-da))
    u=sub(b,a); du=sub(db,da); v=sub(c,a); dv=sub(dc,da); w=sub(p,a); dw=sub(dp,da)
    c0=dot(cross(u,v),w)
    c1=dot(cross(du,v),w)+dot(cross(u,dv),w)+dot(cross(u,v),dw)
    c2=dot(cross(du,dv),w)+dot(cross(du,v),dw)+dot(cross(u,dv),dw)
    c3=dot(cross(du,dv),dw)
    return c0,c1,c2,c3
def f_direct(t,p,a,b,c,dp,da,db,dc):
    P=add(p,mul(t,dp)); Aa=add(a,mul(t,da)); B=add(b,mul(t,db)); Cc=add(c,mul(t,dc))
    return dot(cross(sub(B,Aa),sub(Cc,Aa)),sub(P,Aa))
pts=[[random.uniform(-1,1) for _ in range(3)] for _ in range(4)]
dps=[[random.uniform(-1,1) for _ in range(3)] for _ in range(4)]
cc=cubic_coeffs(*pts,*dps)
for t in [0.0,0.37,1.0]:
    print(f"t={t} poly={cc[0]+cc[1]*t+cc[2]*t*t+cc[3]*t**3:+.12f} direct={f_direct(t,*pts,*dps):+.12f}")
p,a,b,cv=pts; dp,da,db,dc=dps
n0=cross(sub(b,a),sub(cv,a)); n1=cross(sub(add(b,db),add(a,da)),sub(add(cv,dc),add(a,da)))
nh=mul(0.5,sub(add(n0,n1),cross(sub(db,da),sub(dc,da))))
A0v=sub(p,a); A1v=sub(add(p,dp),add(a,da))
bz=[dot(A0v,n0),(2*dot(A0v,nh)+dot(A1v,n0))/3,(2*dot(A1v,nh)+dot(A0v,n1))/3,dot(A1v,n1)]
for t in [0.0,0.37,1.0]:
    B=bz[0]*(1-t)**3+3*bz[1]*t*(1-t)**2+3*bz[2]*t*t*(1-t)+bz[3]*t**3
    print(f"t={t} bernstein={B:+.12f}")

print("\n== pressure force = -P grad V on a closed mesh ==")
# octahedron, outward CCW
V=[[1,0,0],[-1,0,0],[0,1,0],[0,-1,0],[0,0,1],[0,0,-1]]
V=[add(v,[random.uniform(-.1,.1) for _ in range(3)]) for v in V]
Fc=[(0,2,4),(2,1,4),(1,3,4),(3,0,4),(2,0,5),(1,2,5),(3,1,5),(0,3,5)]
def vol(Vs): return sum(dot(Vs[i],cross(Vs[j],Vs[k])) for i,j,k in Fc)/6
print("volume>0 (outward orientation):",vol(V)>0)
def gradV_area(Vs):
    g=[[0,0,0] for _ in Vs]
    for i,j,k in Fc:
        N=cross(sub(Vs[j],Vs[i]),sub(Vs[k],Vs[i]))   # = 2 A n
        for v in (i,j,k): g[v]=add(g[v],mul(1/6,N))   # (1/3) A n
    return g
gf=fd_grad(vol,V); g=gradV_area(V)
print("grad V = (1/3) sum_j A_j n_j : rel err",f"{relerr(g,gf):.1e}")
# paper version: |(1/3) sum A_j| * unit area-weighted normal
gp=[]
for vi in range(len(V)):
    Asum=0; Nsum=[0,0,0]
    for i,j,k in Fc:
        if vi in (i,j,k):
            N=cross(sub(V[j],V[i]),sub(V[k],V[i])); Asum+=0.5*norm(N); Nsum=add(Nsum,N)
    gp.append(mul(Asum/3,normalize(Nsum)))
print("paper form (unit normal * sum A/3) vs exact: rel diff",f"{relerr(gp,g):.2e}")

# ---- part 3 ----
s=1.3
Fb=[[s,0.0],[0.0,1.0]]
print("stvk", energy_P('stvk',Fb)[0], (mu+lam/2)*(s*s-1)**2/4)
print("coro", energy_P('coro',Fb)[0], (mu+lam/2)*(s-1)**2)
print("linear", energy_P('linear',Fb)[0], (mu+lam/2)*(s-1)**2)
print("mr", energy_P('mr',Fb)[0], (C10+C01)*(s-1/s)**2)
# sign(I4) for Fbar = diag(-s,1), a=(1,0)
for s in [0.5,2.0]:
    Fb=[[-s,0.0],[0.0,1.0]]; a=[1.0,0.0]
    R,r=polar_so2(Fb); S=matmul(T(R),Fb)
    I4=S[0][0]; I5=s*s; J=-s
    print(f"s={s}: I4={I4:+.3f}  (I5+J)/rho={(I5+J)/r:+.3f}")
# PK1 vs FD in Fbar for each model
import random
random.seed(3)
Fb=[[1.1,0.2],[-0.1,0.9]]
for m in ['stvk','coro','linear','mr','astvk','asqrt','aarap']:
    psi,P=energy_P(m,Fb); err=0
    for i in range(2):
        for j in range(2):
            Fp=[r[:] for r in Fb]; Fm=[r[:] for r in Fb]; h=1e-6
            Fp[i][j]+=h; Fm[i][j]-=h
            d=(energy_P(m,Fp)[0]-energy_P(m,Fm)[0])/(2*h)
            err=max(err,abs(d-P[i][j]))
    print(m,"PK1 FD max abs err",f"{err:.1e}")
# PBD halfway property on bending hinge (k=1): h' = h/2

# ---- part 4 ----
random.seed(11)
# generic PBD projection on triangle StVK with C=kE: invariance in k; C=sqrt(2E) = 2x step
X=X; Dm,Ar,N,_,_=rest_frame(*X)
x=[add(X[i],[random.uniform(-.1,.1) for _ in range(3)]) for i in range(3)]
w=[1.0,0.7,1.3]
E,g,_=tri_energy_grad('stvk',x,X,N)
G=sum(w[i]*dot(g[i],g[i]) for i in range(3))
for k in [1.0,1e-3,1e4]:
    dx=[mul(-(k*E)*(k*w[i])/(k*k*G),g[i]) for i in range(3)]
    print("k=",k,"dx0=",[f"{c:.6e}" for c in dx[0]])
dxs=[mul(-2*E*w[i]/G,g[i]) for i in range(3)]
print("sqrt form dx0=",[f"{c:.6e}" for c in dxs[0]])
# XPBD sqrt form with alpha->0 equals sqrt-PBD
C=math.sqrt(2*E); at=1e-14; lam=0.0
sig=C*(C+at*lam)/(G+at*C*C)
print("xpbd(alpha~0) dx0=",[f"{c:.6e}" for c in mul(-sig*w[0],g[0])])
