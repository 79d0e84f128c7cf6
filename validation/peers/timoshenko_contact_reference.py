"""Independent reference for strikes near a support: a linear Timoshenko beam with Hertz contact.

Written for the review of 2026-11-27 (strikes near a support; validation/REFERENCES.md 1.4 and
1.5), independently of the toolkit: 2-node elements with the exact static stiffness of a
Timoshenko beam (Friedman & Kosmatka 1993, "An improved two-node Timoshenko beam finite element",
Computers & Structures 47; their consistent translational and rotary mass), k = 5/6, a mesh graded
from `hmin` at the impact point, Newmark average acceleration (no numerical damping), the Hertz
force K = 4/3 E* sqrt(R) solved each step by a scalar Newton iteration on the beam's precomputed
influence vector; support reactions from K u + M a. Halving both hmin (0.2 -> 0.1 mm) and the step
(40 -> 20 ns) moves the peak force, the largest displacement at the ball and the clamp's moment by
less than 1e-4. Checks: at c = 1 mm from a clamp u = 1.9806e-7 m against the static
F (c^3/(3EI) + c/(kGA)) = 1.977e-7 m at the peak force.

Usage (the paper's strip, 9 g ball of radius 5 mm at 1.9809 m/s, gravity off, 0.2 ms):
    python timoshenko_contact_reference.py pinned-pinned 0.002
prints the peak force (N), the largest displacement at the ball (m) and the support reactions'
largest (N, N m). Outside the build, the tests and CI (validation/peers/README.md).
"""
import numpy as np, scipy.sparse as sp, scipy.sparse.linalg as spl

def iie(L, EI, kGA, rhoA, rhoI):
    phi = 12*EI/(kGA*L**2)
    c = EI/((1+phi)*L**3)
    K = c*np.array([[12, 6*L, -12, 6*L],[6*L,(4+phi)*L**2,-6*L,(2-phi)*L**2],
                    [-12,-6*L,12,-6*L],[6*L,(2-phi)*L**2,-6*L,(4+phi)*L**2]])
    # consistent mass (Friedman & Kosmatka 1993), translational + rotary
    p=phi; d=(1+p)**2
    mt = rhoA*L/(210*d)*np.array([
        [70*p*p+147*p+78, (35*p*p+77*p+44)*L/4, 35*p*p+63*p+27, -(35*p*p+63*p+26)*L/4],
        [0, (7*p*p+14*p+8)*L*L/4, (35*p*p+63*p+26)*L/4, -(7*p*p+14*p+6)*L*L/4],
        [0,0,70*p*p+147*p+78, -(35*p*p+77*p+44)*L/4],
        [0,0,0,(7*p*p+14*p+8)*L*L/4]])
    mr = rhoI/(30*d*L)*np.array([
        [36, -(15*p-3)*L, -36, -(15*p-3)*L],
        [0, (10*p*p+5*p+4)*L*L, (15*p-3)*L, (5*p*p-5*p-1)*L*L],
        [0,0,36,(15*p-3)*L],
        [0,0,0,(10*p*p+5*p+4)*L*L]])
    M = mt+mr
    M = np.triu(M)+np.triu(M,1).T
    return K, M

def mesh(L, c, hmin, hmax, grow=1.08, extra=()):
    pts = {0.0, L, c, *extra}
    # graded from c both ways
    for side in (-1, 1):
        x, h = c, hmin
        while True:
            x += side*h
            if x <= 0 or x >= L: break
            pts.add(x); h = min(h*grow, hmax)
    # graded near supports too
    xs = np.array(sorted(pts))
    return xs

def build(xs, E, nu, rho, b, t, eb=False):
    I=b*t**3/12; A=b*t; G=E/(2*(1+nu)); EI=E*I; kGA=5/6*G*A
    if eb: kGA=1e30
    rhoA=rho*A; rhoI=0.0 if eb else rho*I
    n=len(xs); N=2*n
    Kr=[];Kc=[];Kv=[];Mv=[]
    for e in range(n-1):
        Ke,Me=iie(xs[e+1]-xs[e],EI,kGA,rhoA,rhoI)
        dofs=[2*e,2*e+1,2*e+2,2*e+3]
        for i in range(4):
            for j in range(4):
                Kr.append(dofs[i]);Kc.append(dofs[j]);Kv.append(Ke[i,j]);Mv.append(Me[i,j])
    K=sp.csr_matrix((Kv,(Kr,Kc)),shape=(N,N)); M=sp.csr_matrix((Mv,(Kr,Kc)),shape=(N,N))
    return K,M,EI,kGA

def bc_dofs(support, n):
    a,bb = support.split('-')
    fixed=[]
    for end,kind in ((0,a),(n-1,bb)):
        if kind in ('clamped','pinned'): fixed.append(2*end)
        if kind=='clamped': fixed.append(2*end+1)
    return fixed

def simulate(L=1.15,b=0.025,t=0.005,E=2.1e11,nu=0.3,rho=7850.,support='clamped-free',
             c=0.001,m=0.009,R=0.005,Eb=2.1e11,nub=0.3,v0=1.98090888,T=2e-4,dt=2e-8,
             hmin=1e-4,hmax=2e-3,grow=1.05,eb=False,extra=(),record=()):
    xs=mesh(L,c,hmin,hmax,grow,extra); n=len(xs)
    K,M,EI,kGA=build(xs,E,nu,rho,b,t,eb)
    N=2*n
    fixed=bc_dofs(support,n); free=np.setdiff1d(np.arange(N),fixed)
    ic=int(np.argmin(abs(xs-c))); assert abs(xs[ic]-c)<1e-12
    Kf=K[free][:,free].tocsc(); Mf=M[free][:,free].tocsc()
    beta,gam=0.25,0.5
    Keff=(Kf+Mf/(beta*dt*dt)).tocsc()
    lu=spl.splu(Keff)
    jc=int(np.where(free==2*ic)[0][0])
    e=np.zeros(len(free)); e[jc]=1.0
    g=lu.solve(e)  # influence of unit force (force pushes beam +w)
    Es=1/((1-nu**2)/E+(1-nub**2)/Eb); kh=4/3*Es*np.sqrt(R)
    u=np.zeros(len(free)); v=np.zeros(len(free)); a=np.zeros(len(free))
    z=0.0; zv=v0  # ball displacement (toward beam, +w) ; starts touching
    F=0.0; out=dict(maxw=0,maxw_t=0,Fmax=0,Fmax_t=0,t_end=None,react=[],rec={r:[] for r in record})
    # reaction: full-vector
    fixed_idx=np.array(fixed)
    steps=int(round(T/dt)); Fprev=0.0; started=False
    hist=[]
    for k in range(steps):
        # beam predictor: Keff u1 = F e + M(u/(b dt2)+v/(b dt)+(1/(2b)-1)a)
        rhs=Mf@(u/(beta*dt*dt)+v/(beta*dt)+(0.5/beta-1)*a)
        u0=lu.solve(rhs)
        # ball (trapezoidal same Newmark): z1 = z + dt zv + dt^2/4 (za + za1), za1=-F1/m
        za=-Fprev/m
        zpred=z+dt*zv+dt*dt*0.25*za
        # solve delta = zpred - dt^2/4 F/m - (u0[jc]+g[jc]F) ; F=kh*max(delta,0)^1.5
        def res(F): 
            d=zpred-dt*dt*0.25*F/m-(u0[jc]+g[jc]*F); return F-kh*max(d,0)**1.5, d
        Fn=max(Fprev,0.0)
        for it in range(100):
            r,d=res(Fn)
            if d<=0: 
                # check F=0
                r0,d0=res(0.0)
                if d0<=0: Fn=0.0; break
            dd=-(dt*dt*0.25/m+g[jc])
            dr=1-kh*1.5*max(d,0)**0.5*dd
            Fn2=Fn-r/dr
            if Fn2<0: Fn2=0.5*Fn
            if abs(Fn2-Fn)<1e-12*max(1,abs(Fn)): Fn=Fn2; break
            Fn=Fn2
        F1=Fn
        u1=u0+g*F1
        a1=(u1-u)/(beta*dt*dt)-v/(beta*dt)-(0.5/beta-1)*a
        v1=v+dt*((1-gam)*a+gam*a1)
        za1=-F1/m
        z=zpred-dt*dt*0.25*F1/m; zv=zv+dt*0.5*(za+za1)
        u,v,a=u1,v1,a1; Fprev=F1
        tk=(k+1)*dt
        if F1>0: started=True
        if started and F1==0 and out['t_end'] is None: out['t_end']=tk
        if u[jc]>out['maxw']: out['maxw']=u[jc]; out['maxw_t']=tk
        if F1>out['Fmax']: out['Fmax']=F1; out['Fmax_t']=tk
        hist.append((tk,F1,u[jc],z))
        if record or fixed:
            full_u=np.zeros(N); full_a=np.zeros(N); full_u[free]=u; full_a[free]=a
            r=(K@full_u+M@full_a)[fixed_idx]
            # external force at contact node not at fixed dofs (c>0)
            out['react'].append(r)
    out['hist']=np.array(hist); out['xs']=xs; out['EI']=EI; out['kGA']=kGA; out['fixed']=fixed
    if out['react']: out['react']=np.array(out['react'])
    return out


if __name__ == "__main__":
    import sys

    support, c = sys.argv[1], float(sys.argv[2])
    o = simulate(support=support, c=c)
    line = "%s c = %g m: peak force %.6g N, largest displacement %.6g m" % (support, c, o["Fmax"], o["maxw"])
    if len(o["react"]):
        line += ", largest reactions " + " ".join("%.5g" % x for x in np.max(np.abs(o["react"]), axis=0))
    print(line)
