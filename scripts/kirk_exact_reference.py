#!/usr/bin/env python3
"""Exact (discrete-ordinate) reference for the Kirk check outside the relations' domain
(canonical_problems.md section 7; the manual, section 7.5.4): a = 0.1 /m, b = 0.9 /m,
Henyey-Greenstein phase function with mean cosine g = 0.8, sun at nadir, no interface (the
beam enters the water unrefracted and nothing is reflected back down at the top), infinitely
deep homogeneous water.

Solved with PythonicDISORT (a Python implementation of Stamnes' DISORT): one layer of optical
depth 400 (c = 1 /m, so optical depth = depth in metres; the light returned from below 400 is
below 1e-60), albedo 0.9, HG Legendre moments g^l, beam cosine 1. Ed(z) = diffuse + direct
downward plane flux. Prints:
  - z1%: the depth where Ed falls to 1 % of Ed(0), by root finding on the continuous solution;
  - R(0) = Eu(0) / Ed(0) just below the top;
  - both at NQuad = 64, 128, 256 (the discretisation error);
  - z1% by log-linear interpolation of Ed on the detector grid conformance/kirk.hpp uses for
    this case (euphotic_grid: planes from 0.6 to 1.4 times Kirk 1994's z1%, a hundredth of it
    apart), against the root (the interpolation error).

Second, for the relations' domain (conformance/kirk.hpp): R(0) of the canonical Petzold phase
function (M93 Table 2, canonical_problems.md section 3: p linear in angle between the 55 nodes,
held at p(0.1 deg) below, normalised) at the k = b_b/(a + b_b) of the scored cases, sun at
nadir, a = 1 /m, WITHOUT the interface (DISORT has none; the scored cases have one), with
delta-M scaling (NQuad = NLeg = 256 moments kept, the 256th as the truncated peak): how R(0)/k
varies with k for this phase function.

Developer tool (needs numpy, scipy, PythonicDISORT); nothing in the build or the tests runs it.
conformance/kirk.hpp embeds the NQuad = 256 values of the HG case it prints:
    /tmp/venv/bin/python scripts/kirk_exact_reference.py
"""
import math

import numpy as np
from numpy.polynomial.legendre import legval
from scipy.optimize import brentq
from PythonicDISORT import pydisort

A, B, G = 0.1, 0.9, 0.8
C = A + B
TAU_BOTTOM = 400.0


def solve(nquad):
    leg = np.array([[G ** l for l in range(nquad)]])
    _, fp, fm, _ = pydisort(np.array([TAU_BOTTOM]), np.array([B / C]), nquad, leg, 1.0, 1.0, 0.0,
                               NLeg=nquad, NFourier=1, only_flux=True)

    def ed(z):
        diffuse, direct = fm(C * z)
        return float(diffuse + direct)

    ed0 = ed(0.0)
    z1 = brentq(lambda z: math.log(ed(z) / ed0) - math.log(0.01), 1.0, 100.0, xtol=1e-10)
    r0 = float(fp(0.0)) / ed0
    return ed, ed0, z1, r0


def kirk_1994_z1():
    g = 1.0 * (2.127 / G - 1.895) - 0.618 / G + 0.490
    return math.log(100.0) / (A * math.sqrt(1.0 + g * B / A))


def interpolated_z1(ed, ed0, z_guess):
    """z1% by log-linear interpolation between the planes of kirk.hpp's euphotic_grid(z_guess)."""
    target = math.log(0.01 * ed0)
    grid = [z_guess * (0.6 + 0.01 * i) for i in range(81)]
    for z_lo, z_hi in zip(grid, grid[1:]):
        l_lo, l_hi = math.log(ed(z_lo)), math.log(ed(z_hi))
        if l_hi <= target:
            return z_lo + (l_lo - target) / (l_lo - l_hi) * (z_hi - z_lo)
    raise ValueError("the grid does not reach z1%")


# M93 Table 2 (canonical_problems.md section 3): angle (deg), p (1/sr).
PETZOLD_TABLE2 = [
    (0.10000, 1.76661e3), (0.12589, 1.29564e3), (0.15849, 9.50172e2), (0.19953, 6.99092e2),
    (0.25119, 5.13687e2), (0.31623, 3.76373e2), (0.39811, 2.76318e2), (0.50119, 2.18839e2),
    (0.63096, 1.44369e2), (0.79433, 1.02241e2), (1.0000, 7.16082e1), (1.2589, 4.95803e1),
    (1.5849, 3.39511e1), (1.9953, 2.28129e1), (2.5119, 1.51622e1), (3.1623, 1.00154e1),
    (3.9811, 6.57957), (5.0119, 4.29530), (6.3096, 2.80690), (7.9433, 1.81927), (10.0, 1.15257),
    (15.0, 4.89344e-1), (20.0, 2.44424e-1), (25.0, 1.47151e-1), (30.0, 8.60848e-2),
    (35.0, 5.93075e-2), (40.0, 4.20985e-2), (45.0, 3.06722e-2), (50.0, 2.27533e-2),
    (55.0, 1.69904e-2), (60.0, 1.31254e-2), (65.0, 1.04625e-2), (70.0, 8.48826e-3),
    (75.0, 6.97601e-3), (80.0, 5.84232e-3), (85.0, 4.95306e-3), (90.0, 4.29232e-3),
    (95.0, 3.78161e-3), (100.0, 3.40405e-3), (105.0, 3.11591e-3), (110.0, 2.91222e-3),
    (115.0, 2.79696e-3), (120.0, 2.68568e-3), (125.0, 2.57142e-3), (130.0, 2.47603e-3),
    (135.0, 2.37667e-3), (140.0, 2.32898e-3), (145.0, 2.31308e-3), (150.0, 2.36475e-3),
    (155.0, 2.50584e-3), (160.0, 2.66183e-3), (165.0, 2.83472e-3), (170.0, 3.03046e-3),
    (175.0, 3.09206e-3), (180.0, 3.15366e-3),
]
PETZOLD_K = (0.005, 0.01, 0.02, 0.05, 0.1, 0.15)  # conformance/kirk.hpp, domain_k()


def petzold_moments(nleg):
    """Legendre moments 0..nleg of the canonical Petzold reading, its b_b/b and mean cosine."""
    nodes = np.array([0.0] + [t for t, _ in PETZOLD_TABLE2])
    values = np.array([PETZOLD_TABLE2[0][1]] + [v for _, v in PETZOLD_TABLE2])
    deg = np.unique(np.concatenate([np.linspace(t0, t1, 400) for t0, t1 in zip(nodes[:-1], nodes[1:])]))
    psi = np.radians(deg)
    weight = 2.0 * np.pi * np.interp(deg, nodes, values) * np.sin(psi)  # p linear in angle
    weight /= np.trapezoid(weight, psi)
    mu = np.cos(psi)
    moments = np.array([np.trapezoid(weight * legval(mu, [0] * l + [1]), psi) for l in range(nleg + 1)])
    back = deg >= 90.0
    return moments, np.trapezoid(weight[back], psi[back]), moments[1]


def petzold_reflectances(nquad=256):
    moments, bb_fraction, mean_cosine = petzold_moments(nquad)
    print(f"\ncanonical Petzold: b_b/b = {bb_fraction:.5f}, mean cosine = {mean_cosine:.4f}; a = 1 /m, sun at nadir, "
          f"no interface, delta-M with NQuad = {nquad}")
    print(f"{'k':>6} {'b/a':>7} {'R(0)':>10} {'R(0)/k':>8}")
    for k in PETZOLD_K:
        b = k / ((1.0 - k) * bb_fraction)
        _, fp, fm, _ = pydisort(np.array([TAU_BOTTOM]), np.array([b / (1.0 + b)]), nquad,
                                moments[None, :nquad], 1.0, 1.0, 0.0, NLeg=nquad, NFourier=1,
                                only_flux=True, f_arr=moments[nquad])
        diffuse, direct = fm(0.0)
        r0 = float(fp(0.0)) / float(diffuse + direct)
        print(f"{k:>6.3f} {b:>7.3f} {r0:>10.6f} {r0 / k:>8.4f}")


def main():
    print(f"HG g = {G}, a = {A} /m, b = {B} /m, sun at nadir, no interface, deep water (tau {TAU_BOTTOM:g})")
    print(f"{'NQuad':>6} {'z1% (m)':>14} {'Kd_bar (1/m)':>14} {'R(0)':>14}")
    results = {}
    for nquad in (64, 128, 256):
        ed, ed0, z1, r0 = solve(nquad)
        results[nquad] = (ed, ed0, z1, r0)
        print(f"{nquad:>6} {z1:>14.6f} {math.log(100.0) / z1:>14.8f} {r0:>14.8f}")
    ed, ed0, z1, r0 = results[256]
    kirk_z1 = kirk_1994_z1()
    zi = interpolated_z1(ed, ed0, kirk_z1)
    print(f"log-linear interpolation on canonical's grid ({0.01 * kirk_z1:.4f} m apart): z1% = {zi:.6f} m "
          f"(relative error {(zi - z1) / z1:+.2e})")
    print(f"Kirk 1994 relation: z1% = {kirk_z1:.4f} m (exact / relation - 1 = {z1 / kirk_z1 - 1.0:+.4f})")
    petzold_reflectances()

if __name__ == "__main__":
    main()
