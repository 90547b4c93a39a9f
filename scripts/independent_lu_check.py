#!/usr/bin/env python3
"""A cross-check of the nadir radiance of canonical problem 2a that shares no code with secchi
(numpy only; not part of the tests): Lu at tau 1, 5 and 10 for the canonical Petzold function
(canonical_problems.md, problem 2: all 55 nodes of Table 2, p linear in angle, p(0.1 deg)
below), w0 = 0.9, c = 1 /m, sun at 60 deg, flat Fresnel surface n = 1.34, infinitely deep.

Photons carry only their direction cosine mu and depth (plane-parallel), free paths from b
with the weight decaying as exp(-a s), Fresnel internal reflection at the surface (analog
choice), Russian roulette below weight 0.01. Lu(tau) is the collision estimate: every
scattering event at depth z >= tau with direction cosine mu adds
    w p_>(psi) exp(-c' (z - tau)),   cos psi = -mu (the angle to straight up),
with p_> the phase function without its peak within psi_t and c' = c - b f(psi_t), f the
peak's share of the scattering (psi_t = 0: the exact p and c). psi_t > 0 is the transmitted
peak of secchi's estimator (optics/phase/cone_average.hpp); comparing psi_t = 2.29 deg (the
collection cone's half-angle) with 5 deg shows its truncation error, and psi_t = 0 shows the
heavy tail of the untruncated estimate (its typical value lies below its mean, and its batch
SE understates its spread). No photon map, no collection volume, no cone average: the numbers
to compare with `canonical --problem 2a` (M93 Table 5: 6.99e-3, 3.26e-3, 1.21e-3).

    python3 scripts/independent_lu_check.py [PHOTONS] [SEED] [PSI_T,...]   (default 4e6 7 0,2.29,5)

4e6 photons take about 7 minutes on one core.
"""
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from independent_ed_check import fresnel_R, read_table  # noqa: E402

W0, A, B, N_WATER, SUN = 0.9, 0.1, 0.9, 1.34, np.radians(60.0)
DEPTHS = np.array([1.0, 5.0, 10.0])


class CanonicalPetzold:
    """p linear in angle between the nodes, p(0.1 deg) below, normalised; sampled by inverting
    its cumulative on a grid of 6e5 angles (trapezoid: relative error of the CDF < 1e-8)."""

    def __init__(self):
        ang, p = read_table()
        nodes = np.radians(ang)
        self.th = np.concatenate([np.linspace(0.0, np.radians(12), 400001), np.linspace(np.radians(12), np.pi, 200001)[1:]])
        raw = np.where(self.th < nodes[0], p[0], np.interp(self.th, nodes, p))
        f = 2 * np.pi * raw * np.sin(self.th)
        cdf = np.concatenate([[0.0], np.cumsum(0.5 * (f[1:] + f[:-1]) * np.diff(self.th))])
        self.p = raw / cdf[-1]
        self.cdf = cdf / cdf[-1]

    def eval(self, cos_psi):
        return np.interp(np.arccos(np.clip(cos_psi, -1.0, 1.0)), self.th, self.p)

    def sample_cos(self, u):
        return np.cos(np.interp(u, self.cdf, self.th))

    def share_within(self, psi):
        return float(np.interp(psi, self.th, self.cdf))


def run(photons, seed, psi_ts, batches=16):
    pf = CanonicalPetzold()
    shares = [pf.share_within(np.radians(t)) if t > 0 else 0.0 for t in psi_ts]
    rng = np.random.default_rng(seed)
    mu0 = np.sqrt(1.0 - (np.sin(SUN) / N_WATER) ** 2)
    transmitted = 1.0 - float(fresnel_R(np.array([np.cos(SUN)]), 1.0, N_WATER)[0])
    out = np.zeros((batches, len(psi_ts), len(DEPTHS)))
    for batch in range(batches):
        m = photons // batches
        mu, z, w = np.full(m, mu0), np.zeros(m), np.full(m, transmitted)
        tally = np.zeros((len(psi_ts), len(DEPTHS)))
        while len(z):
            s = -np.log(rng.random(len(z))) / B
            # Flights that reach the surface: Fresnel reflection (analog) or escape, then on.
            up = z + mu * s < 0.0
            while np.any(up):
                to_surface = np.where(up, -z / mu, 0.0)
                w = w * np.exp(-A * to_surface)
                reflect = up & (rng.random(len(z)) < fresnel_R(-mu, N_WATER, 1.0))
                keep = ~(up & ~reflect)
                s = np.where(up, s - to_surface, s)
                mu = np.where(reflect, -mu, mu)
                z = np.where(up, 0.0, z)
                mu, z, w, s = mu[keep], z[keep], w[keep], s[keep]
                up = z + mu * s < 0.0
            w = w * np.exp(-A * s)
            z = z + mu * s
            for i, psi_t in enumerate(psi_ts):
                p = pf.eval(-mu)
                if psi_t > 0:
                    p = np.where(-mu > np.cos(np.radians(psi_t)), 0.0, p)
                c_ray = 1.0 - B * shares[i]
                for j, depth in enumerate(DEPTHS):
                    below = z >= depth
                    tally[i, j] += np.sum((w * p)[below] * np.exp(-c_ray * (z[below] - depth)))
            cos_psi = pf.sample_cos(rng.random(len(z)))
            phi = 2 * np.pi * rng.random(len(z))
            sin_psi = np.sqrt(np.maximum(0.0, 1.0 - cos_psi ** 2))
            mu = np.clip(mu * cos_psi + np.sqrt(np.maximum(0.0, 1.0 - mu ** 2)) * sin_psi * np.cos(phi), -1.0, 1.0)
            low = w < 1e-2
            survive = rng.random(len(z)) < 0.1
            w = np.where(low & survive, w / 0.1, w)
            keep = ~low | survive
            mu, z, w = mu[keep], z[keep], w[keep]
        out[batch] = tally * np.cos(SUN) / m  # per unit E_perp
    return shares, out.mean(axis=0), out.std(axis=0, ddof=1) / np.sqrt(batches)


def main():
    photons = int(float(sys.argv[1])) if len(sys.argv) > 1 else 4_000_000
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 7
    psi_ts = [float(x) for x in sys.argv[3].split(",")] if len(sys.argv) > 3 else [0.0, 2.29, 5.0]
    with np.errstate(invalid="ignore", divide="ignore"):
        shares, mean, se = run(photons, seed, psi_ts)
    for i, psi_t in enumerate(psi_ts):
        cells = "  ".join(f"Lu({d:g}) {mean[i, j]:.4e} ({100 * se[i, j] / mean[i, j]:.1f} %)" for j, d in enumerate(DEPTHS))
        print(f"psi_t {psi_t:4.2f} deg (f = {shares[i]:.3f}):  {cells}")


if __name__ == "__main__":
    main()
