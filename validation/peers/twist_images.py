#!/usr/bin/env python3
"""The exact twist of a struck section of a uniform strip in Saint-Venant torsion, by images.

An independent reference, not a peer tool (validation/REFERENCES.md 1.9, "Torsion fronts on a
mesh"). Saint-Venant torsion is the wave equation rho Ip theta_tt = G J theta_xx + T(t) delta(x - a),
which does not disperse: a torque impulse I(t) = int T at x = a sends the twist I / (2 Z) both
ways (Z = sqrt(G J rho Ip), the torsional impedance), and ends that hold the twist (clamped,
pinned = forked) reflect it inverted. The struck section's twist is then the sum over images:

    theta(a, t) = (1 / 2Z) sum_k [ I(t - |2 k L| / c) - I(t - |2 a - 2 k L| / c) ],   c = sqrt(G J / rho Ip).

The torque is the contact force times the offset, T = e F(t), F read from a history CSV that
`cargo xtask simulate SCENE --history H.csv` writes (columns time_s, force_n). Usage, for the
paper's strip pinned at both ends struck at 0.4 m 10 mm off its centre line (numpy only):

    python3 validation/peers/twist_images.py H.csv --at 0.4 --offset 0.01

It prints the plateau e J / (2 Z) (J the impulse) and the largest |theta(a, t)| over the history's
window with its time. The strip's J is the rectangle's series (as the modal method's), Ip the
polar moment (b t^3 + t b^3) / 12.

With `--rate-at X` it also prints the largest Saint-Venant shear stress at the section x = X over
the window, tau = k G t theta_x (Timoshenko & Goodier, Theory of Elasticity, 3rd ed., sec. 109:
k = 1 - (8 / pi^2) sum_{n odd} 1 / (n^2 cosh(n pi b / 2 t)), b the long side, t the short), from
the images' twist rate

    theta_x(x, t) = -(1 / 2 G J) sum_k s_k sign(x - x_k) T(t - |x - x_k| / c),

the images x_k of the struck section with their signs s_k: an end that holds the twist
(clamped, pinned = forked) reflects it inverted, a free end (`--ends held-free`: held at x = 0,
free at x = L) upright, where the twist rate vanishes. Images that fall on one another (a
strike at a free end) add. For the paper's tip struck 10 mm off its centre line:

    python3 validation/peers/twist_images.py H.csv --at 1.15 --offset 0.01 --ends held-free --rate-at 0
"""
import argparse

import numpy as np


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("history", help="a history CSV of `cargo xtask simulate --history`")
    p.add_argument("--at", type=float, required=True, help="struck section a (m)")
    p.add_argument("--offset", type=float, required=True, help="the strike's offset e (m)")
    p.add_argument("--length", type=float, default=1.15)
    p.add_argument("--width", type=float, default=0.025)
    p.add_argument("--thickness", type=float, default=0.005)
    p.add_argument("--youngs-modulus", type=float, default=2.1e11)
    p.add_argument("--poisson-ratio", type=float, default=0.3)
    p.add_argument("--density", type=float, default=7850.0)
    p.add_argument("--ends", choices=["held-held", "held-free"], default="held-held",
                   help="x = 0 and x = L: held (clamped, pinned) or free")
    p.add_argument("--rate-at", type=float, help="a section x (m) for the torsion shear")
    a = p.parse_args()
    b, t = max(a.width, a.thickness), min(a.width, a.thickness)
    n = np.arange(1, 200, 2)
    j = b * t**3 / 3 * (1 - 192 / np.pi**5 * (t / b) * np.sum(np.tanh(n * np.pi * b / (2 * t)) / n**5))
    polar = a.width * a.thickness * (a.width**2 + a.thickness**2) / 12
    g = a.youngs_modulus / (2 * (1 + a.poisson_ratio))
    c = np.sqrt(g * j / (a.density * polar))
    z = np.sqrt(g * j * a.density * polar)
    d = np.genfromtxt(a.history, delimiter=",", names=True)
    time, force = d["time_s"], d["force_n"]
    impulse = np.concatenate([[0.0], np.cumsum(0.5 * (force[1:] + force[:-1]) * np.diff(time))])
    impulse *= a.offset

    def torque_impulse(s):
        return np.interp(s, time, impulse, left=0.0)

    # The images: reflections about x = 0 (sign r0) and x = L (sign rl) make the translations
    # x -> x + 2 L (sign r0 rl): a + 2 m L with sign (r0 rl)^|m|, -a + 2 m L with r0 (r0 rl)^|m|.
    r0, rl = -1.0, (-1.0 if a.ends == "held-held" else 1.0)
    count = int(np.ceil(c * time[-1] / (2 * a.length))) + 2
    images = []
    for m in range(-count, count + 1):
        images.append((a.at + 2 * m * a.length, (r0 * rl) ** abs(m)))
        images.append((-a.at + 2 * m * a.length, r0 * (r0 * rl) ** abs(m)))
    grid = np.linspace(0.0, time[-1], 200001)
    theta = np.zeros_like(grid)
    for x_k, s_k in images:
        theta += s_k * torque_impulse(grid - abs(a.at - x_k) / c)
    theta /= 2 * z
    i = int(np.argmax(np.abs(theta)))
    print(f"c_t {c:.2f} m/s, Z {z:.5e} N m s, torque impulse {impulse[-1]:.5e} N m s")
    print(f"plateau {impulse[-1] / (2 * z):.5e} rad; largest |twist| {abs(theta[i]):.5e} rad at {grid[i] * 1e3:.4f} ms")
    if a.rate_at is not None:
        torque = a.offset * force
        rate = np.zeros_like(grid)
        for x_k, s_k in images:
            lag = grid - abs(a.rate_at - x_k) / c
            rate -= s_k * np.sign(a.rate_at - x_k) * np.interp(lag, time, torque, left=0.0)
        rate /= 2 * g * j
        k = 1 - 8 / np.pi**2 * np.sum(1 / (n**2 * np.cosh(np.minimum(n * np.pi * b / (2 * t), 300.0))))
        tau = k * g * t * np.abs(rate)
        i = int(np.argmax(tau))
        print(f"torsion shear at x = {a.rate_at} m: largest {tau[i]:.6e} Pa at {grid[i] * 1e3:.4f} ms (k = {k:.6f})")


if __name__ == "__main__":
    main()
