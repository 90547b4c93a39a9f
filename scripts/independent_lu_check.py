#!/usr/bin/env python3
"""A cross-check of the nadir radiance of canonical problems 2a and 3 that shares no code with secchi
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
    python3 scripts/independent_lu_check.py --w0 0.2 [PHOTONS] [SEED] [PSI_T,...]   (problem 2b)
    python3 scripts/independent_lu_check.py --problem3 [PHOTONS] [SEED] [PSI_T,...]

4e6 photons take about 7 minutes on one core. With --problem3, the same estimate of Lu at 5,
25 and 60 m in canonical problem 3's stratified water (Problem3Water, run_problem3).
"""
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from independent_ed_check import fresnel_R, read_table  # noqa: E402

W0, N_WATER, SUN = 0.9, 1.34, np.radians(60.0)
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


def run(photons, seed, psi_ts, w0=W0, batches=16):
    A, B = 1.0 - w0, w0  # c = 1 /m
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


class Problem3Water:
    """Canonical problem 3's profile (canonical_problems.md): C(z) = 0.2 + 144/(9 sqrt(2 pi))
    exp(-(z - 17)^2 / 162), a = 0.0257 + 0.04 C^0.602, b_w = 0.0029 (Rayleigh), b_p = 0.33 C^0.62
    (Petzold), on a 1 cm grid to 400 m, with the cumulative integrals of a, b and b_p."""

    def __init__(self):
        self.z = np.linspace(0.0, 400.0, 40001)
        chl = 0.2 + 144.0 / (9.0 * np.sqrt(2 * np.pi)) * np.exp(-(self.z - 17.0) ** 2 / (2 * 81.0))
        self.a = 0.0257 + 0.04 * chl ** 0.602
        self.bp = 0.33 * chl ** 0.62
        self.b = 0.0029 + self.bp
        cum = lambda k: np.concatenate([[0.0], np.cumsum(0.5 * (k[1:] + k[:-1]) * np.diff(self.z))])
        self.A, self.B, self.BP = cum(self.a), cum(self.b), cum(self.bp)

    def integral(self, table, z):
        return np.interp(z, self.z, table)

    def depth_at(self, b_integral):
        return np.interp(b_integral, self.B, self.z)


def rayleigh(cos_psi):
    return 3.0 / (16.0 * np.pi) * (1.0 + cos_psi ** 2)


def rayleigh_sample_cos(u):
    # inverse of the Rayleigh CDF (1 + cos^2) on mu: the real root of mu^3 + 3 mu = 8 u - 4
    q = 4.0 * u - 2.0
    r = np.cbrt(q + np.sqrt(q * q + 1.0))
    return r - 1.0 / r


def run_problem3(photons, seed, psi_t, depths=(5.0, 25.0, 60.0), batches=16, roulette=1e-4):
    """Problem 3's Lu at `depths` (m), by the collision estimate as run() does, in the stratified
    water: free paths from b(z) (inverted on the cumulative table), absorption exp(-int a),
    the Rayleigh or the Petzold component chosen by b_w/b and b_p/b at the event, and the
    mixture's phase function (b_w p_R + b_p p_P,>)/b in the estimate, the ray attenuating with
    c' = c - b_p f (Rayleigh's share within psi_t, < 4e-4, is not removed). Roulette below
    weight 1e-4 (deep light matters here)."""
    pf, water = CanonicalPetzold(), Problem3Water()
    f = pf.share_within(np.radians(psi_t)) if psi_t > 0 else 0.0
    depths = np.array(depths)
    rng = np.random.default_rng(seed)
    mu0 = np.sqrt(1.0 - (np.sin(SUN) / N_WATER) ** 2)
    transmitted = 1.0 - float(fresnel_R(np.array([np.cos(SUN)]), 1.0, N_WATER)[0])
    C = water.A + water.B  # int c
    ray = C - f * water.BP  # int c'
    out = np.zeros((batches, len(depths)))
    for batch in range(batches):
        m = photons // batches
        mu, z, w = np.full(m, mu0), np.zeros(m), np.full(m, transmitted)
        tally = np.zeros(len(depths))
        while len(z):
            tau = -np.log(rng.random(len(z)))
            b0 = water.integral(water.B, z)
            target = b0 + tau * mu
            up = target < 0.0
            while np.any(up):  # to the surface: Fresnel reflection (analog) or escape
                w = w * np.where(up, np.exp(-water.integral(water.A, z) / np.abs(mu)), 1.0)
                tau = np.where(up, tau - b0 / np.abs(mu), tau)
                reflect = up & (rng.random(len(z)) < fresnel_R(-mu, N_WATER, 1.0))
                keep = ~(up & ~reflect)
                mu = np.where(reflect, -mu, mu)
                z = np.where(up, 0.0, z)
                mu, z, w, tau = mu[keep], z[keep], w[keep], tau[keep]
                b0 = water.integral(water.B, z)
                target = b0 + tau * mu
                up = target < 0.0
            z1 = np.where(np.abs(mu) > 1e-9, water.depth_at(np.minimum(target, water.B[-1])), z)
            w = w * np.exp(-np.abs(water.integral(water.A, z1) - water.integral(water.A, z)) / np.maximum(np.abs(mu), 1e-9))
            z = z1
            bp = np.interp(z, water.z, water.bp)
            bt = 0.0029 + bp
            p_part = pf.eval(-mu)
            if psi_t > 0:
                p_part = np.where(-mu > np.cos(np.radians(psi_t)), 0.0, p_part)
            phase = (0.0029 * rayleigh(-mu) + bp * p_part) / bt
            for j, depth in enumerate(depths):
                below = z >= depth
                att = np.interp(z[below], water.z, ray) - np.interp(depth, water.z, ray)
                tally[j] += np.sum((w * phase)[below] * np.exp(-att))
            particle = rng.random(len(z)) < bp / bt
            u = rng.random(len(z))
            cos_psi = np.where(particle, pf.sample_cos(u), rayleigh_sample_cos(u))
            phi = 2 * np.pi * rng.random(len(z))
            sin_psi = np.sqrt(np.maximum(0.0, 1.0 - cos_psi ** 2))
            mu = np.clip(mu * cos_psi + np.sqrt(np.maximum(0.0, 1.0 - mu ** 2)) * sin_psi * np.cos(phi), -1.0, 1.0)
            low = w < roulette
            survive = rng.random(len(z)) < 0.1
            w = np.where(low & survive, w / 0.1, w)
            keep = (~low | survive) & (z < 395.0)
            mu, z, w = mu[keep], z[keep], w[keep]
        out[batch] = tally * np.cos(SUN) / m
    return depths, out.mean(axis=0), out.std(axis=0, ddof=1) / np.sqrt(batches)


def main():
    argv = sys.argv[1:]
    w0 = W0
    if "--w0" in argv:  # --w0 0.2: problem 2b (M93 Table 5: 5.47e-5, 6.24e-7, 4.02e-9)
        at = argv.index("--w0")
        w0 = float(argv[at + 1])
        del argv[at:at + 2]
    args = [a for a in argv if a != "--problem3"]
    photons = int(float(args[0])) if len(args) > 0 else 4_000_000
    seed = int(args[1]) if len(args) > 1 else 7
    psi_ts = [float(x) for x in args[2].split(",")] if len(args) > 2 else [0.0, 2.29, 5.0]
    with np.errstate(invalid="ignore", divide="ignore"):
        if "--problem3" in sys.argv:
            for psi_t in psi_ts:
                depths, mean, se = run_problem3(photons, seed, psi_t)
                cells = "  ".join(f"Lu({d:g} m) {mean[j]:.4e} ({100 * se[j] / mean[j]:.1f} %)" for j, d in enumerate(depths))
                print(f"problem 3, psi_t {psi_t:4.2f} deg:  {cells}", flush=True)
            return
        shares, mean, se = run(photons, seed, psi_ts, w0)
    for i, psi_t in enumerate(psi_ts):
        cells = "  ".join(f"Lu({d:g}) {mean[i, j]:.4e} ({100 * se[i, j] / mean[i, j]:.1f} %)" for j, d in enumerate(DEPTHS))
        print(f"psi_t {psi_t:4.2f} deg (f = {shares[i]:.3f}):  {cells}")


if __name__ == "__main__":
    main()
