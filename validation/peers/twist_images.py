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

    grid = np.linspace(0.0, time[-1], 200001)
    theta = np.zeros_like(grid)
    images = int(np.ceil(c * time[-1] / (2 * a.length))) + 2
    for k in range(-images, images + 1):
        theta += torque_impulse(grid - abs(2 * k * a.length) / c)
        theta -= torque_impulse(grid - abs(2 * a.at - 2 * k * a.length) / c)
    theta /= 2 * z
    i = int(np.argmax(np.abs(theta)))
    print(f"c_t {c:.2f} m/s, Z {z:.5e} N m s, torque impulse {impulse[-1]:.5e} N m s")
    print(f"plateau {impulse[-1] / (2 * z):.5e} rad; largest |twist| {abs(theta[i]):.5e} rad at {grid[i] * 1e3:.4f} ms")


if __name__ == "__main__":
    main()
