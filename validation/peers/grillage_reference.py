"""Independent reference: planar grillage (structure in x-y plane, strike along -z) of
Timoshenko beam elements (exact static interpolation, consistent mass incl. rotary inertia)
+ Saint-Venant torsion (linear elements, polar inertia), point masses (m, J1, J2), springs,
supports; modal superposition with Hertz contact integrated by solve_ivp (DOP853), optional
residual flexibility (quasi-static share of truncated modes, in series with the contact).
Written from the physics for a review of the modal method on structures; not derived from the
repository's code. An independent reference, not a peer tool (`pip install numpy scipy`).

Usage: python validation/peers/grillage_reference.py [--refine N]
runs the cantilever with a tip mass of validation/REFERENCES.md 1.10 (the paper's 25 x 5 mm strip,
1.15 m, clamped; 0.1 kg at the tip with rotary inertia J1 = 1e-5, J2 = 2e-5 kg m^2; a 10 mm steel
ball at 1 m/s struck at 1.10 m, gravity off, 2 ms) at 5 mm / N elements, modes up to omega t_c = 20
and 40, with the residual flexibility, and prints each run's contacts, largest displacement and
largest bending stress with where (about a minute at N = 2).
"""
import argparse
import numpy as np
from scipy.linalg import eigh
from scipy.integrate import solve_ivp

E_ = 2.1e11; NU = 0.3; RHO = 7850.0


def rect_J_roark(w, t):
    b, c = max(w, t), min(w, t); r = c / b
    return b * c**3 * (1/3 - 0.21 * r * (1 - r**4 / 12))


def rect_shear_k(w, t):
    b, tt = max(w, t), min(w, t)
    s = 0.0
    for i in range(200):
        n = 2 * i + 1
        a = n * np.pi * b / (2 * tt)
        s += 1 / (n * n * np.cosh(a)) if a < 700 else 0
    return 1 - 8 / np.pi**2 * s


class Sec:
    def __init__(self, w, t, E=E_, nu=NU, rho=RHO, kshear=5/6):
        G = E / (2 * (1 + nu))
        A = w * t; I = w * t**3 / 12; I3 = t * w**3 / 12
        self.w, self.t, self.E, self.G = w, t, E, G
        self.EI = E * I; self.kGA = kshear * G * A; self.GJ = G * rect_J_roark(w, t)
        self.rhoA = rho * A; self.rhoI = rho * I; self.rhoIp = rho * (I + I3)
        self.ktau = rect_shear_k(w, t)


GX, GW = np.polynomial.legendre.leggauss(6)


def timo_elem(L, s, timoshenko=True):
    g = s.EI / s.kGA if timoshenko else 0.0
    # a -> nodal dofs [w1, th1, w2, th2]
    def wrow(x): return np.array([1, x, x*x, x**3])
    def trow(x): return np.array([0, 1, 2*x, 3*x*x + 6*g])
    C = np.array([wrow(0), trow(0), wrow(L), trow(L)])
    Ci = np.linalg.inv(C)
    K = np.zeros((4, 4)); M = np.zeros((4, 4))
    for xi, wt in zip(GX, GW):
        x = (xi + 1) * L / 2; ww = wt * L / 2
        Nw = wrow(x) @ Ci; Nt = trow(x) @ Ci
        dNt = np.array([0, 0, 2, 6*x]) @ Ci
        dNw = np.array([0, 1, 2*x, 3*x*x]) @ Ci
        gam = dNw - Nt
        K += ww * (s.EI * np.outer(dNt, dNt) + s.kGA * np.outer(gam, gam))
        M += ww * (s.rhoA * np.outer(Nw, Nw) + (s.rhoI * np.outer(Nt, Nt) if timoshenko else 0))
    # curvature at midpoint and ends
    kap = lambda x: np.array([0, 0, 2, 6*x]) @ Ci
    return K, M, kap


class Model:
    """members: list of dict(p0, p1, n, sec). Nodes merged by coordinates."""
    def __init__(self, members, timoshenko=True):
        self.nodes = []; self.elems = []
        def node(p):
            for i, q in enumerate(self.nodes):
                if np.linalg.norm(np.array(q) - p) < 1e-9: return i
            self.nodes.append(np.array(p, float)); return len(self.nodes) - 1
        s_acc = 0.0; self.node_s = {}
        for m in members:
            p0, p1 = np.array(m['p0'], float), np.array(m['p1'], float)
            Lm = np.linalg.norm(p1 - p0); e = (p1 - p0) / Lm
            for k in range(m['n']):
                a = p0 + (p1 - p0) * k / m['n']; b = p0 + (p1 - p0) * (k + 1) / m['n']
                i, j = node(a), node(b)
                self.node_s.setdefault(i, s_acc + Lm * k / m['n'])
                self.node_s.setdefault(j, s_acc + Lm * (k + 1) / m['n'])
                self.elems.append(dict(i=i, j=j, L=Lm / m['n'], e=e, sec=m['sec'],
                                       smid=s_acc + Lm * (k + .5) / m['n']))
            s_acc += Lm
        n = len(self.nodes); self.ndof = 3 * n
        K = np.zeros((self.ndof, self.ndof)); M = np.zeros_like(K)
        self.kap = []; self.tw = []; self.kpos = []; self.kel = []; self.elems_done = []
        for el in self.elems:
            s = el['sec']; L = el['L']; e = el['e']
            p = np.array([e[1], -e[0]])  # slope beta = r . p
            Kb, Mb, kap = timo_elem(L, s, timoshenko)
            # local [w1, b1, t1, w2, b2, t2] from global [w, rx, ry] x2
            T = np.zeros((6, 6))
            for a in (0, 1):
                T[3*a, 3*a] = 1
                T[3*a+1, 3*a+1:3*a+3] = p
                T[3*a+2, 3*a+1:3*a+3] = e[:2]
            Kl = np.zeros((6, 6)); Ml = np.zeros((6, 6))
            ib = [0, 1, 3, 4]; it = [2, 5]
            Kl[np.ix_(ib, ib)] = Kb; Ml[np.ix_(ib, ib)] = Mb
            Kl[np.ix_(it, it)] = s.GJ / L * np.array([[1, -1], [-1, 1]])
            Ml[np.ix_(it, it)] = s.rhoIp * L / 6 * np.array([[2, 1], [1, 2]])
            d = [3*el['i'], 3*el['i']+1, 3*el['i']+2, 3*el['j'], 3*el['j']+1, 3*el['j']+2]
            K[np.ix_(d, d)] += T.T @ Kl @ T; M[np.ix_(d, d)] += T.T @ Ml @ T
            # stress recovery rows: curvature at mid (bending), twist rate
            P = np.array([[1,0,0,0,0,0],[0,1,0,0,0,0],[0,0,0,1,0,0],[0,0,0,0,1,0]])
            for xx in (0.0, L/2, L):
                rowk = np.zeros(self.ndof); rowk[d] = (kap(xx) @ P) @ T
                self.kap.append(rowk); self.kpos.append(el['smid'] - L/2 + xx); self.kel.append(len(self.elems_done))
            self.elems_done.append(1)
            rowt = np.zeros(self.ndof); rowt[d] = np.array([0, 0, -1/L, 0, 0, 1/L]) @ T
            self.tw.append(rowt)
        self.K, self.M = K, M
        self.kap = np.array(self.kap); self.tw = np.array(self.tw)
        self.fixed = set()

    def find(self, s):
        for i, si in self.node_s.items():
            if abs(si - s) < 1e-9: return i
        raise ValueError(f'no node at s={s}')

    def support(self, s, kind):
        i = self.find(s)
        self.fixed |= {3*i} | ({3*i+1, 3*i+2} if kind == 'clamped' else set()) | ({3*i+1} if kind == 'forked_x' else set())

    def mass(self, s, m, J1=0.0, J2=0.0):
        i = self.find(s); self.M[3*i, 3*i] += m
        el = [e for e in self.elems if e['i'] == i or e['j'] == i][0]
        e = el['e'][:2]; p = np.array([e[1], -e[0]])
        self.M[3*i+1:3*i+3, 3*i+1:3*i+3] += J1 * np.outer(e, e) + J2 * np.outer(p, p)

    def spring(self, s, kz, k1=0.0, k2=0.0):
        i = self.find(s); self.K[3*i, 3*i] += kz
        el = [e for e in self.elems if e['i'] == i or e['j'] == i][0]
        e = el['e'][:2]; p = np.array([e[1], -e[0]])
        self.K[3*i+1:3*i+3, 3*i+1:3*i+3] += k1 * np.outer(e, e) + k2 * np.outer(p, p)

    def finish(self, site_s, offset=0.0):
        self.free = np.array([d for d in range(self.ndof) if d not in self.fixed])
        f = self.free
        self.Kf = self.K[np.ix_(f, f)]; self.Mf = self.M[np.ix_(f, f)]
        self.site = list(f).index(3 * self.find(site_s))
        r = np.zeros(len(f)); r[self.site] = 1.0
        if offset:
            i = self.find(site_s); el = [e for e in self.elems if e['i'] == i or e['j'] == i][0]
            for k, c in zip((1, 2), el['e'][:2]):
                if 3*i+k in list(f): r[list(f).index(3*i+k)] += offset * c
        self.rsite = r
        self.kapf = self.kap[:, f]; self.twf = self.tw[:, f]
        w2, V = eigh(self.Kf, self.Mf)
        self.omega_all = np.sqrt(np.clip(w2, 0, None)); self.V_all = V
        self.ustat = np.linalg.solve(self.Kf, self.rsite)
        self.flex = self.rsite @ self.ustat
        return self

    def nodal_twist_rows(self):
        rows = []; pos = []
        for el in self.elems:
            for a, key in ((0, 'i'), (1, 'j')):
                i = el[key]; r = np.zeros(self.ndof); r[3*i+1:3*i+3] = el['e'][:2]
                rows.append(r[self.free]); pos.append(self.node_s[i])
        return np.array(rows), np.array(pos)


def impact(mod, m_ball, R, v0, Eb=E_, nub=NU, wcut=None, nmodes=None, residual=True,
           t_end=2e-3, dt_free=2e-7, rtol=1e-10, want_stress=True, mid_only=False):
    Es = 1 / ((1 - nub**2) / Eb + (1 - NU**2) / E_)
    Kh = 4/3 * Es * np.sqrt(R)
    om = mod.omega_all; V = mod.V_all
    sel = om <= wcut if wcut is not None else np.arange(len(om)) < nmodes
    om = om[sel]; V = V[:, sel]
    phi = mod.rsite @ V
    r0 = mod.rsite
    rp = r0 - mod.Mf @ (V @ (V.T @ r0))
    xr = np.linalg.solve(mod.Kf, rp)
    cr = rp @ xr if residual else 0.0
    cr_diff = mod.flex - np.sum(phi**2 / om**2)
    n = len(om)
    kapm = mod.kapf @ V; twm = mod.twf @ V
    kap_r = mod.kapf @ xr if residual else 0 * mod.kapf[:, 0]  # deflated static solve
    tw_r = mod.twf @ xr if residual else 0 * mod.twf[:, 0]

    def force(dt_):
        if dt_ <= 0: return 0.0
        if cr == 0: return Kh * dt_**1.5
        s = min(dt_, (dt_ / (cr * Kh))**(2/3))
        for _ in range(60):
            g = s + cr * Kh * s**1.5 - dt_; dg = 1 + 1.5 * cr * Kh * s**0.5
            s2 = max(s - g / dg, 0.5 * s)
            if abs(s2 - s) < 1e-15 * max(s, 1e-30): s = s2; break
            s = s2
        return Kh * s**1.5

    def rhs(t, y):
        u, v = y[0], y[1]; q = y[2:2+n]; qd = y[2+n:]
        F = force(u - phi @ q)
        return np.concatenate(([v, -F / m_ball], qd, -om**2 * q + phi * F))

    def sep(t, y): return y[0] - phi @ y[2:2+n]
    sep.terminal = True; sep.direction = -1

    t0 = 0.0; y = np.zeros(2 + 2*n); y[1] = v0
    contacts = []; umax = (0, 0); smax = (0, 0, 0); tmax = (0, 0, 0)
    twr, twpos = mod.nodal_twist_rows(); twm_n = twr @ V
    twist_max = (0, 0, 0)
    Es_h = np.array([mod.elems[k]['sec'].E * mod.elems[k]['sec'].t / 2 for k in mod.kel])
    kpos = np.array(mod.kpos)
    if mid_only:
        msk = np.zeros(len(kpos)); msk[1::3] = 1
        Es_h = Es_h * msk
    tau_f = np.array([el['sec'].ktau * el['sec'].G * min(el['sec'].w, el['sec'].t) for el in mod.elems])
    smid = np.array([el['smid'] for el in mod.elems])
    while t0 < t_end:
        # contact phase
        y[2:2+n]  # start with delta = 0 moving in
        sol = solve_ivp(rhs, (t0, t_end), y, method='DOP853', rtol=rtol, atol=1e-16,
                        events=sep, dense_output=True, max_step=(t_end)/50)
        tt = np.linspace(t0, sol.t[-1], 2000)
        Y = sol.sol(tt)
        Fs = np.array([force(Y[0, k] - phi @ Y[2:2+n, k]) for k in range(len(tt))])
        ks = int(np.argmax(Fs))
        t1 = sol.t[-1]; y = sol.y[:, -1].copy()
        contacts.append(dict(start=t0, dur=t1 - t0, peak=Fs.max(), vin=Y[1, 0], vout=y[1],
                             tpeak=tt[ks], impulse=np.trapezoid(Fs, tt)))
        w = phi @ Y[2:2+n] + Fs * cr
        k = np.argmax(np.abs(w)); umax = max(umax, (abs(w[k]), tt[k]))
        if want_stress:
            S = np.abs(Es_h[:, None] * (kapm @ Y[2:2+n] + np.outer(kap_r, Fs)))
            i, j = np.unravel_index(np.argmax(S), S.shape)
            if S[i, j] > smax[0]: smax = (S[i, j], kpos[i], tt[j])
            T = np.abs(tau_f[:, None] * (twm @ Y[2:2+n] + np.outer(tw_r, Fs)))
            i, j = np.unravel_index(np.argmax(T), T.shape)
            if T[i, j] > tmax[0]: tmax = (T[i, j], smid[i], tt[j])
            TW = np.abs(twm_n @ Y[2:2+n])
            i, j = np.unravel_index(np.argmax(TW), TW.shape)
            if TW[i, j] > twist_max[0]: twist_max = (TW[i, j], twpos[i], tt[j])
        if t1 >= t_end: break
        # free flight: analytic
        q0 = y[2:2+n]; qd0 = y[2+n:]; u0, v = y[0], y[1]
        nextc = None; t = t1
        while t < t_end:
            ts = np.arange(t, min(t + 2e-4, t_end) + 1e-15, dt_free)
            c = np.cos(np.outer(om, ts - t1)); s_ = np.sin(np.outer(om, ts - t1))
            Q = q0[:, None] * c + (qd0 / om)[:, None] * s_
            w = phi @ Q
            k = np.argmax(np.abs(w)); umax = max(umax, (abs(w[k]), ts[k]))
            if want_stress:
                S = np.abs(Es_h[:, None] * (kapm @ Q))
                i, j = np.unravel_index(np.argmax(S), S.shape)
                if S[i, j] > smax[0]: smax = (S[i, j], kpos[i], ts[j])
                T = np.abs(tau_f[:, None] * (twm @ Q))
                i, j = np.unravel_index(np.argmax(T), T.shape)
                if T[i, j] > tmax[0]: tmax = (T[i, j], smid[i], ts[j])
                TW = np.abs(twm_n @ Q)
                i, j = np.unravel_index(np.argmax(TW), TW.shape)
                if TW[i, j] > twist_max[0]: twist_max = (TW[i, j], twpos[i], ts[j])
            gap = u0 + v * (ts - t1) - w
            idx = np.nonzero((gap[1:] > 0) & (gap[:-1] <= 0))[0]
            if len(idx) and ts[idx[0]+1] > t1 + 1e-9:
                # refine by bisection
                a, b = ts[idx[0]], ts[idx[0]+1]
                def g(tq):
                    return u0 + v*(tq-t1) - phi @ (q0*np.cos(om*(tq-t1)) + qd0/om*np.sin(om*(tq-t1)))
                for _ in range(60):
                    mth = 0.5*(a+b)
                    if g(mth) > 0: b = mth
                    else: a = mth
                nextc = a; break
            t = ts[-1] + dt_free
        if nextc is None: break
        tc = nextc
        q = q0*np.cos(om*(tc-t1)) + qd0/om*np.sin(om*(tc-t1))
        qd = -q0*om*np.sin(om*(tc-t1)) + qd0*np.cos(om*(tc-t1))
        y = np.concatenate(([u0 + v*(tc-t1), v], q, qd)); t0 = tc
    # energy
    return dict(n=n, om=om, cr=cr, cr_diff=cr_diff, contacts=contacts, umax=umax, smax=smax, tmax=tmax,
                twist=twist_max, k_static=1/mod.flex)


def report(r, name=''):
    c = r['contacts']
    print(f'== {name}: {r["n"]} modes (max omega {r["om"].max():.4e}), residual {r["cr"]:.4e} (diff form {r["cr_diff"]:.3e}) m/N, k_static {r["k_static"]:.6e} N/m')
    for i, cc in enumerate(c):
        print(f'  contact {i+1}: start {cc["start"]*1e6:.3f} us dur {cc["dur"]*1e6:.3f} us peak {cc["peak"]:.3f} N vin {cc["vin"]:.5f} vout {cc["vout"]:.5f} impulse {cc["impulse"]:.6f}')
    print(f'  restitution(first) {-c[0]["vout"]/c[0]["vin"]:.5f}; n contacts {len(c)}')
    print(f'  umax {r["umax"][0]:.5e} m at t {r["umax"][1]:.5e}; eq static F {r["umax"][0]*r["k_static"]:.5e} N')
    print(f'  smax {r["smax"][0]:.5e} Pa at s {r["smax"][1]:.4f} t {r["smax"][2]:.4e}')
    print(f'  tau max {r["tmax"][0]:.5e} Pa at s {r["tmax"][1]:.4f} t {r["tmax"][2]:.4e}')
    print(f'  twist max {r["twist"][0]:.5e} rad at s {r["twist"][1]:.4f} t {r["twist"][2]:.4e}')


def tip_mass(refine):
    """The cantilever with a tip mass (see the module text) on 5 mm / `refine` elements."""
    s5 = Sec(0.025, 0.005)
    m = Model([dict(p0=[0, 0, 0], p1=[1.1, 0, 0], n=220 * refine, sec=s5),
               dict(p0=[1.1, 0, 0], p1=[1.15, 0, 0], n=10 * refine, sec=s5)])
    m.support(0, 'clamped')
    m.mass(1.15, 0.1, J1=1e-5, J2=2e-5)
    m.finish(1.1)
    return m


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--refine", type=int, default=1)
    args = parser.parse_args()
    model = tip_mass(args.refine)
    ball_radius = 0.01
    ball_mass = RHO * 4 / 3 * np.pi * ball_radius ** 3
    for factor in (20, 40):
        # omega t_c <= factor for the estimated contact duration 6.4e-5 s.
        r = impact(model, ball_mass, ball_radius, 1.0, wcut=factor / 6.4e-5, residual=True,
                   t_end=2e-3)
        report(r, f"tip mass, 5 mm / {args.refine} elements, omega t_c <= {factor}")


if __name__ == "__main__":
    main()
