#!/usr/bin/env python3
"""Reference data for the paper's straight-line path (eq. 18-20), computed
independently of elasticarm with scipy (DOP853 at rtol 1e-12 + fsolve), on the
physical branch reached the same way the paper's arm is: the T = 0 edge at the
cable angle (gravity continuation from the straight weightless beam), then
continuation in cable length.

    /usr/bin/python3 tests/gen/gen_paper_line.py > data/reference/paper_line_path.csv

Writes beta, cable_length_m, cable_angle_rad, tension_N, theta0_rad,
kappa0_per_m, shoulder_torque_Nm (Table 1 arm, payload factor 0, 6 steps).
"""
import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

RHO, MH, L, EI, XC, YC, G = 0.501, 0.230, 0.914, 0.705, 0.098, -0.006, 9.81


def tip(alpha, T, th0, k0, g=G):
    def f(s, y):
        W = (MH + RHO * (L - s)) * g
        return [y[1], (W * np.cos(y[0]) - T * np.sin(y[0] - alpha)) / EI,
                np.cos(y[0]), np.sin(y[0])]
    return solve_ivp(f, (0, L), [th0, k0, 0, 0], method="DOP853",
                     rtol=1e-12, atol=1e-13).y[:, -1]


def edge(alpha):
    # straight weightless beam with its tip on the ray: closed form
    th0 = alpha + np.arcsin((YC * np.cos(alpha) - XC * np.sin(alpha)) / L)
    z = np.array([th0, 0.0])
    for g in np.linspace(0, G, 41)[1:]:
        def r(z, g=g):
            th, k, x, y = tip(alpha, 0.0, z[0], z[1], g)
            return [k, (y - YC) * np.cos(alpha) - (x - XC) * np.sin(alpha)]
        z = fsolve(r, z, xtol=1e-13)
    th, k, x, y = tip(alpha, 0.0, z[0], z[1])
    return z, np.hypot(x - XC, y - YC)


def solve_cable(Lc, alpha):
    z0, Le = edge(alpha)
    z = np.array([0.0, z0[0], z0[1]])
    for lc in np.linspace(Le, Lc, 41)[1:]:
        tx, ty = XC + lc * np.cos(alpha), YC + lc * np.sin(alpha)
        def r(z, tx=tx, ty=ty):
            th, k, x, y = tip(alpha, z[0], z[1], z[2])
            return [k, x - tx, y - ty]
        z = fsolve(r, z, xtol=1e-13)
    return z


def main():
    print("beta,cable_length_m,cable_angle_rad,tension_N,theta0_rad,kappa0_per_m,"
          "shoulder_torque_Nm")
    for k in range(7):
        b = k / 6
        x, y = 0.3 * b + 0.3, -0.2
        Lc, a = np.hypot(x - XC, y - YC), np.arctan2(y - YC, x - XC)
        T, th0, k0 = solve_cable(Lc, a)
        print(f"{b:.12g},{Lc:.15g},{a:.15g},{T:.15g},{th0:.15g},{k0:.15g},{EI * k0:.15g}")


if __name__ == "__main__":
    main()
