"""Natural frequencies of a stepped cantilever by transfer matrices (Euler-Bernoulli): the
reference of validation/REFERENCES.md 1.12 for simo_beam::modes_below on a stepped member.

A steel strip (E = 2.1e11 Pa, rho = 7850 kg/m^3), 25 mm wide, clamped at x = 0: 0.5 m of
2 mm thickness, then 0.5 m of 1 mm, on one centre line, bending across the thickness. In each
uniform piece u = [w, w', w'', w'''] is carried by the Krylov-Duncan functions of beta^4 =
rho A omega^2 / EI (K1 = (cosh + cos)/2, K2 = (sinh + sin)/(2 beta), K3 = (cosh - cos)/(2 beta^2),
K4 = (sinh - sin)/(2 beta^3), K1' = beta^4 K4, K2' = K1, K3' = K2, K4' = K3); at the step w, w',
EI w'' and EI w''' are continuous. Clamped at 0 (w = w' = 0), free at L (w'' = w''' = 0): the
2 x 2 determinant of the free end's rows over the two unknowns w''(0), w'''(0) vanishes at the
natural frequencies, found by a scan and brentq to 1e-14. Prints the first five omega (rad/s).

    python validation/peers/stepped_beam_reference.py      (numpy, scipy; a second)
"""

import numpy as np
from scipy.optimize import brentq

E, RHO, WIDTH = 2.1e11, 7850.0, 0.025
PIECES = [(0.5, 0.002), (0.5, 0.001)]  # (length (m), thickness (m)), from the clamp


def carry(length, thickness, omega):
    """u(length) = F u(0) within one uniform piece."""
    area, inertia = WIDTH * thickness, WIDTH * thickness ** 3 / 12.0
    b = (RHO * area * omega ** 2 / (E * inertia)) ** 0.25
    x = b * length
    ch, c, sh, s = np.cosh(x), np.cos(x), np.sinh(x), np.sin(x)
    k1, k2 = (ch + c) / 2, (sh + s) / (2 * b)
    k3, k4 = (ch - c) / (2 * b ** 2), (sh - s) / (2 * b ** 3)
    b4 = b ** 4
    return np.array([
        [k1, k2, k3, k4],
        [b4 * k4, k1, k2, k3],
        [b4 * k3, b4 * k4, k1, k2],
        [b4 * k2, b4 * k3, b4 * k4, k1],
    ])


def determinant(omega):
    u = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])  # w''(0), w'''(0)
    previous = None
    for length, thickness in PIECES:
        ei = E * WIDTH * thickness ** 3 / 12.0
        if previous is not None:
            u = u.copy()
            u[2:] *= previous / ei  # EI w'' and EI w''' continuous at the step
        u = carry(length, thickness, omega) @ u
        previous = ei
    free = u[2:]
    # Scaled by the rows' size: the hyperbolic terms grow as exp(beta L).
    return np.linalg.det(free) / (np.linalg.norm(free[0]) * np.linalg.norm(free[1]))


def main():
    grid = np.linspace(0.5, 1500.0, 300000)
    values = [determinant(w) for w in grid]
    roots = []
    for a, b, fa, fb in zip(grid[:-1], grid[1:], values[:-1], values[1:]):
        if fa * fb < 0:
            roots.append(brentq(determinant, a, b, xtol=1e-14, rtol=1e-15))
        if len(roots) == 5:
            break
    for k, r in enumerate(roots):
        print("mode %d: omega = %.10f rad/s" % (k + 1, r))


if __name__ == "__main__":
    main()
