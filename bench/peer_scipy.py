#!/usr/bin/env python3
"""The statics sweep of bench_statics solved the way a user might without
elasticarm: scipy's solve_ivp for eq. (11) and fsolve for g* = 0 (eq. 15),
warm-started from the neighbour with the same secant predictor.

Run with Debian's python3 (python3-scipy) in the directory where
bench_statics wrote bench_statics_ref.csv:
    /usr/bin/python3 ../bench/peer_scipy.py [repeats]
Prints median time per solve and the error against the same reference
(rkf45 at 1e-13) as bench_statics, so the two tables can be set side by side.
"""
import sys
import time

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

RHO, MH, L, EI, XC, YC, G = 0.501, 0.230, 0.914, 0.705, 0.098, -0.006, 9.81


def shoot(alpha, T, th0, k0, method, rtol, atol):
    ca, sa = np.cos(alpha), np.sin(alpha)

    def f(s, y):
        th, ka = y[0], y[1]
        W = (MH + RHO * (L - s)) * G
        c, sn = np.cos(th), np.sin(th)
        return [ka, (W * c - T * (sn * ca - c * sa)) / EI, c, sn]

    sol = solve_ivp(f, (0.0, L), [th0, k0, 0.0, 0.0], method=method, rtol=rtol, atol=atol)
    return sol.y[:, -1]


def main():
    reps = int(sys.argv[1]) if len(sys.argv) > 1 else 3
    ref = np.loadtxt("bench_statics_ref.csv", delimiter=",", skiprows=1)
    na, nl = 10, 40
    cases = [("DOP853", 1e-8, 1e-10), ("DOP853", 1e-10, 1e-12), ("DOP853", 1e-12, 1e-13),
             ("RK45", 1e-8, 1e-10)]
    print("| peer | rtol / atol | median us/solve | max tip err [m] | max rel err T |"
          " max rel err theta0 | branch jumps |")
    print("|---|---|---|---|---|---|---|")
    for method, rtol, atol in cases:
        times = []
        for _ in range(reps):
            out = np.zeros((na * nl, 3))
            t0 = time.perf_counter()
            for i in range(na):
                for j in range(nl):
                    Lc, alpha = ref[i * nl + j, 0], ref[i * nl + j, 1]
                    tx, ty = XC + Lc * np.cos(alpha), YC + Lc * np.sin(alpha)
                    if j == 0:
                        guess = ref[i * nl, 2:5]
                    elif j == 1:
                        guess = out[i * nl]
                    else:
                        guess = 2 * out[i * nl + j - 1] - out[i * nl + j - 2]

                    def g(z):
                        th, ka, x, y = shoot(alpha, z[0], z[1], z[2], method, rtol, atol)
                        return [ka, x - tx, y - ty]

                    out[i * nl + j] = fsolve(g, guess, xtol=1e-12)
            times.append((time.perf_counter() - t0) / (na * nl))
        etip = eT = eth = 0.0
        jumps = 0
        for k in range(na * nl):
            if abs(out[k, 0] - ref[k, 2]) > 1e-3 * abs(ref[k, 2]):
                jumps += 1  # fsolve left the physical branch: not an accuracy figure
                continue
            Lc, alpha = ref[k, 0], ref[k, 1]
            tx, ty = XC + Lc * np.cos(alpha), YC + Lc * np.sin(alpha)
            th, ka, x, y = shoot(alpha, *out[k], "DOP853", 1e-13, 1e-14)
            etip = max(etip, np.hypot(x - tx, y - ty))
            eT = max(eT, abs(out[k, 0] - ref[k, 2]) / abs(ref[k, 2]))
            eth = max(eth, abs(out[k, 1] - ref[k, 3]) / abs(ref[k, 3]))
        print(f"| scipy {method} + fsolve | {rtol:.0e} / {atol:.0e} | "
              f"{1e6 * float(np.median(times)):.0f} | {etip:.2e} | {eT:.2e} | {eth:.2e} |"
              f" {jumps} |")


if __name__ == "__main__":
    main()
