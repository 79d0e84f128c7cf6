"""The paper's tip impact by Goldsmith's modal model in scipy: what a user writes instead.

Peer measurement for the modal method (issue "Speed against error"); not part of the build, the
tests or CI. The cantilever (validation/scenes/paper-tip.toml) by its first N Euler-Bernoulli
modes at the tip, the ball a point mass, Hertz contact F = K delta^(3/2), gravity off, integrated
by solve_ivp (DOP853, rtol 1e-10) with an event at every change of contact. Usage:

    pip install numpy scipy
    python validation/peers/scipy_modal_tip.py --modes 256 --end-time 0.005

It prints the integration's wall time and the contacts (start, duration, peak force).

Made as fast as scipy allows at that tolerance: the right-hand side vectorised over the modes
with its stiffness and gains computed once and the modal accelerations written in place (4.5 ->
3.4 s on the 2-core machine of the speed issue, 256 modes over 5 ms), the approach at the outputs
in one product. DOP853 then takes about 5600 steps a millisecond (rtol 1e-10 limits it, not
max_step), and scipy's per-step Python (the stages, the error norm, the event check) is about
as much as the right-hand side's 67000 calls.
"""
import argparse
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

L, WIDTH, THICK = 1.15, 0.025, 0.005
E, NU, RHO = 2.1e11, 0.3, 7850.0
R_BALL, M_BALL = 0.005, 0.009
SPEED = (2 * 9.81 * 0.2) ** 0.5


def cantilever_roots(n):
    """b_n L: roots of cos x + 1 / cosh x = 0 (validation/REFERENCES.md 1.1)."""
    roots = []
    for k in range(1, n + 1):
        guess = (2 * k - 1) * np.pi / 2
        f = lambda x: np.cos(x) + 1.0 / np.cosh(x)
        roots.append(brentq(f, guess - 0.5, guess + 0.5) if k < 30 else guess)
    return np.array(roots)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--modes", type=int, default=256)
    parser.add_argument("--end-time", type=float, default=0.005)
    args = parser.parse_args()
    area, inertia = WIDTH * THICK, WIDTH * THICK ** 3 / 12
    rho_a = RHO * area
    omega = cantilever_roots(args.modes) ** 2 * np.sqrt(E * inertia / (rho_a * L ** 4))
    # Modes normalised to integral phi^2 dx = L: phi_n(L) = 2 (-1)^(n+1); modal mass rho A L.
    tip = 2.0 * (-1.0) ** np.arange(args.modes)
    e_star = E / (2 * (1 - NU ** 2))
    k_hertz = 4.0 / 3.0 * e_star * np.sqrt(R_BALL)
    n = args.modes

    def approach(y):
        return y[2 * n] - tip @ y[:n]

    stiffness = -omega ** 2
    gain = tip / (rho_a * L)

    def rhs(_, y):
        delta = approach(y)
        force = k_hertz * delta ** 1.5 if delta > 0 else 0.0
        dy = np.empty_like(y)
        dy[:n] = y[n:2 * n]
        np.multiply(stiffness, y[:n], out=dy[n:2 * n])
        if force:
            dy[n:2 * n] += gain * force
        dy[2 * n] = y[2 * n + 1]
        dy[2 * n + 1] = -force / M_BALL
        return dy

    def touch(_, y):
        return approach(y)

    y = np.zeros(2 * n + 2)
    y[2 * n + 1] = SPEED
    t, contacts, clock = 0.0, [], time.perf_counter()
    times, forces = [], []
    while t < args.end_time:
        # Integrate to the next contact change (the event), then step over it.
        sol = solve_ivp(rhs, (t, args.end_time), y, method="DOP853", rtol=1e-10, atol=1e-14,
                        events=touch, dense_output=False, max_step=args.end_time / 2000)
        times.extend(sol.t)
        # The approach at every output point at once (a loop over them in Python cost a
        # tenth of the run).
        gaps = sol.y[2 * n] - tip @ sol.y[:n]
        forces.extend(k_hertz * np.clip(gaps, 0, None) ** 1.5)
        if sol.status == 1 and sol.t_events[0].size:
            t = sol.t_events[0][-1] + 1e-12
            y = sol.y_events[0][-1]
            if t >= args.end_time:
                break
            y = sol.sol(t) if sol.sol is not None else y
        else:
            break
    wall = time.perf_counter() - clock
    times, forces = np.array(times), np.array(forces)
    on = forces > 0
    edges = np.flatnonzero(np.diff(on.astype(int)))
    starts = ([0] if on[0] else []) + [i + 1 for i in edges if not on[i]]
    print(f"scipy DOP853: {n} modes, {args.end_time * 1e3} ms, wall time {wall:.3f} s, {len(starts)} contacts")
    for k, i in enumerate(starts[:5]):
        j = i
        while j < len(on) and on[j]:
            j += 1
        print(f"contact {k + 1}: start {times[i] * 1e6:.2f} us, duration {(times[min(j, len(times) - 1)] - times[i]) * 1e6:.2f} us, peak {forces[i:j].max():.1f} N")


if __name__ == "__main__":
    main()
