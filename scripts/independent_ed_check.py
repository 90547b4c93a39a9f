#!/usr/bin/env python3
"""Independent Monte Carlo for Mobley et al. 1993 canonical problems 1a, 2a, 2b.

A cross-check of secchi's transport that shares no code with it (numpy only; not part of
the tests). Usage:
    python3 scripts/independent_ed_check.py 2a:A 3e7 [out.json]   # problem:definition photons
    python3 scripts/independent_ed_check.py 1a 1e7
    python3 scripts/independent_ed_check.py pf 0                   # the two Petzold definitions' moments
docs/conformance.md gives the results.

Plane-parallel, infinitely deep homogeneous water, flat surface (n = 1.340),
black sky, sun at 60 deg zenith, E_perp = 1 => Ed(air) = cos(60) = 0.5.

Quantity: downward plane irradiance Ed(tau) at tau = 1, 5, 10.

Method (unbiased):
  * photon weight starts at Ed(air) * T_Fresnel(60 deg) (deterministic split
    at the surface; the reflected part leaves and is never counted below).
  * depth in optical units; free path ~ Exp(1).
  * implicit capture: w *= w0 at each collision; Russian roulette below WMIN
    (survive with prob 0.1, weight x10).
  * upward photons reaching the surface: weight split, w *= R_Fresnel(inside)
    (R = 1 beyond the critical angle), direction mirrored, photon continues.
  * Ed tally: expected-value (conditional-expectation) version of the plane
    crossing tally.  For every flight that starts at depth z going down
    (mu > 0) with weight w, the probability that the flight crosses the plane
    tau_k > z is exp(-(tau_k - z)/mu); we add w*exp(-(tau_k - z)/mu) instead of
    the 0/1 indicator.  This is exactly unbiased (the flight itself is still
    sampled normally) and includes the uncollided beam exactly.
  * only the direction cosine mu matters in a horizontally homogeneous slab:
    after scattering mu' = mu cos(psi) + sqrt(1-mu^2) sin(psi) cos(phi),
    phi uniform in [0, 2pi) -- exact for the azimuthally symmetric problem.

Phase function definitions for problem 2 (M93 Table 2):
  A "canonical":  f(psi) = 2 pi p(psi) sin(psi) linear in psi between nodes,
                  p = p(0.1deg) (0.1deg/psi)^1.346 below 0.1 deg (f ~ psi^-0.346).
  B "linear-flat": p linear in psi between nodes, times exact sin(psi);
                  p = p(0.1deg) constant below 0.1 deg.
Both normalised numerically.
"""
import sys
import time
import numpy as np

N_WATER = 1.340
SUN_ZEN_DEG = 60.0
ED_AIR = np.cos(np.radians(SUN_ZEN_DEG))  # E_perp = 1 on plane normal to sun
TAUS = np.array([1.0, 5.0, 10.0])
WMIN = 1e-3          # roulette threshold (weights relative to 1 entering photon)
SURV = 0.1           # roulette survival probability

TABLE = """
0.10000 1.76661e3    1.0000 7.16082e1    15.0 4.89344e-1   65.0 1.04625e-2   115.0 2.79696e-3   165.0 2.83472e-3
0.12589 1.29564e3    1.2589 4.95803e1    20.0 2.44424e-1   70.0 8.48826e-3   120.0 2.68568e-3   170.0 3.03046e-3
0.15849 9.50172e2    1.5849 3.39511e1    25.0 1.47151e-1   75.0 6.97601e-3   125.0 2.57142e-3   175.0 3.09206e-3
0.19953 6.99092e2    1.9953 2.28129e1    30.0 8.60848e-2   80.0 5.84232e-3   130.0 2.47603e-3   180.0 3.15366e-3
0.25119 5.13687e2    2.5119 1.51622e1    35.0 5.93075e-2   85.0 4.95306e-3   135.0 2.37667e-3
0.31623 3.76373e2    3.1623 1.00154e1    40.0 4.20985e-2   90.0 4.29232e-3   140.0 2.32898e-3
0.39811 2.76318e2    3.9811 6.57957      45.0 3.06722e-2   95.0 3.78161e-3   145.0 2.31308e-3
0.50119 2.18839e2    5.0119 4.29530      50.0 2.27533e-2  100.0 3.40405e-3   150.0 2.36475e-3
0.63096 1.44369e2    6.3096 2.80690      55.0 1.69904e-2  105.0 3.11591e-3   155.0 2.50584e-3
0.79433 1.02241e2    7.9433 1.81927      60.0 1.31254e-2  110.0 2.91222e-3   160.0 2.66183e-3
                    10.0    1.15257
"""


def read_table():
    vals = [float(t) for t in TABLE.split()]
    ang = np.array(vals[0::2])
    p = np.array(vals[1::2])
    o = np.argsort(ang)
    return ang[o], p[o]


# ---------------------------------------------------------------- Fresnel
def fresnel_R(cos_i, n1, n2):
    """Unpolarised Fresnel reflectance, incidence cosine cos_i in medium n1."""
    cos_i = np.clip(np.abs(cos_i), 0.0, 1.0)
    sin_i = np.sqrt(np.maximum(0.0, 1.0 - cos_i ** 2))
    sin_t = n1 / n2 * sin_i
    R = np.ones_like(cos_i)
    ok = sin_t < 1.0
    ci = cos_i[ok]
    ct = np.sqrt(1.0 - sin_t[ok] ** 2)
    rs = (n1 * ci - n2 * ct) / (n1 * ci + n2 * ct)
    rp = (n1 * ct - n2 * ci) / (n1 * ct + n2 * ci)
    R[ok] = 0.5 * (rs * rs + rp * rp)
    return R


# ---------------------------------------------------------------- phase functions
class TabulatedPF:
    """pdf over psi: head segment [0, psi0] + piecewise-linear f on a fine grid.

    Within each fine sub-interval f is linear, the CDF quadratic, inverted exactly.
    For definition A, f is exactly linear between table nodes, so the sampling is
    exact.  For B, f = 2 pi p_lin sin(psi) is approximated as linear over each of
    NSUB sub-intervals per table interval (relative error ~1e-6).
    """

    def __init__(self, definition, nsub=200):
        ang, p = read_table()
        psi_n = np.radians(ang)
        self.definition = definition
        psi0, p0 = psi_n[0], p[0]
        self.psi0 = psi0
        # fine grid
        grid = [psi_n[0:1]]
        for i in range(len(psi_n) - 1):
            grid.append(np.linspace(psi_n[i], psi_n[i + 1], nsub + 1)[1:])
        x = np.concatenate(grid)
        if definition == "A":
            fn = 2 * np.pi * p * np.sin(psi_n)
            f = np.interp(x, psi_n, fn)  # linear in psi between nodes (exact)
            head = 2 * np.pi * p0 * psi0 ** 2 / 0.654
        elif definition == "B":
            f = 2 * np.pi * np.interp(x, psi_n, p) * np.sin(x)
            head = 2 * np.pi * p0 * (1.0 - np.cos(psi0))
        else:
            raise ValueError(definition)
        f[-1] = max(f[-1], 0.0)
        h = np.diff(x)
        cell = 0.5 * (f[:-1] + f[1:]) * h
        C = np.concatenate([[0.0], np.cumsum(cell)]) + head
        self.raw_total = C[-1]
        self.head = head
        self.x, self.f, self.h, self.C = x, f, h, C
        # diagnostics
        tot = C[-1]
        i90 = np.argmin(np.abs(x - np.pi / 2))
        assert abs(x[i90] - np.pi / 2) < 1e-12
        self.bb = (tot - C[i90]) / tot
        # mean cosine: integrate f cos on the fine grid (+ head ~ cos~1)
        g = f * np.cos(x)
        # finer check by Simpson-like trapezoid on fine grid (adequate)
        mc_body = np.sum(0.5 * (g[:-1] + g[1:]) * h)
        if definition == "A":
            # head: int f cos, cos ~ 1 - psi^2/2
            mc_head = head * (1 - 0.5 * psi0 ** 2 * 0.654 / 2.654)
        else:
            mc_head = 2 * np.pi * p0 * 0.5 * np.sin(psi0) ** 2
        self.gbar = (mc_body + mc_head) / tot

    def sample_cos(self, rng, n):
        u = rng.random(n)
        t = u * self.raw_total
        out_psi = np.empty(n)
        hd = t < self.head
        uh = t[hd] / self.head
        if self.definition == "A":
            out_psi[hd] = self.psi0 * uh ** (1.0 / 0.654)
        else:
            # f ~ sin(psi): cos uniform between cos(psi0) and 1
            c0 = np.cos(self.psi0)
            out_psi[hd] = np.arccos(1.0 - uh * (1.0 - c0))
        b = ~hd
        tb = t[b]
        i = np.searchsorted(self.C, tb, side="right") - 1
        i = np.clip(i, 0, len(self.h) - 1)
        r = tb - self.C[i]
        fi = self.f[i]
        a = (self.f[i + 1] - fi) / (2.0 * self.h[i])
        disc = np.maximum(fi * fi + 4.0 * a * r, 0.0)
        s = 2.0 * r / (fi + np.sqrt(disc))
        s = np.clip(s, 0.0, self.h[i])
        out_psi[b] = self.x[i] + s
        return np.cos(out_psi), np.sin(out_psi)


class RayleighPF:
    bb = 0.5
    gbar = 0.0
    raw_total = 1.0

    def sample_cos(self, rng, n):
        q = 4.0 * rng.random(n) - 2.0
        d = np.sqrt(q * q + 1.0)
        x = np.cbrt(q + d) + np.cbrt(q - d)
        x = np.clip(x, -1.0, 1.0)
        return x, np.sqrt(1.0 - x * x)


# ---------------------------------------------------------------- transport
def tally_down(z, mu, w, acc):
    """Expected downward plane-crossing contribution of flights starting at z."""
    m = mu > 0
    if not np.any(m):
        return
    zz, mm, ww = z[m], mu[m], w[m]
    for k, tk in enumerate(TAUS):
        sel = zz < tk
        if np.any(sel):
            acc[k] += np.sum(ww[sel] * np.exp(-(tk - zz[sel]) / mm[sel]))


def run_chunk(n, w0, pf, rng):
    acc = np.zeros(len(TAUS))
    th = np.radians(SUN_ZEN_DEG)
    T = 1.0 - fresnel_R(np.array([np.cos(th)]), 1.0, N_WATER)[0]
    mu0 = np.sqrt(1.0 - (np.sin(th) / N_WATER) ** 2)
    z = np.zeros(n)
    mu = np.full(n, mu0)
    w = np.full(n, T)
    tally_down(z, mu, w, acc)
    ncoll = 0
    while z.size:
        s = rng.standard_exponential(z.size)
        znew = z + mu * s
        up = znew < 0.0
        # surface hits (upward flights reaching tau = 0)
        if np.any(up):
            R = fresnel_R(mu[up], N_WATER, 1.0)
            w[up] *= R
            mu[up] = -mu[up]
            znew[up] = 0.0
        z = znew
        # collisions
        c = ~up
        nc = int(np.count_nonzero(c))
        ncoll += nc
        w[c] *= w0
        cs, sn = pf.sample_cos(rng, nc)
        phi = rng.random(nc) * (2.0 * np.pi)
        muc = mu[c]
        mun = muc * cs + np.sqrt(np.maximum(0.0, 1.0 - muc * muc)) * sn * np.cos(phi)
        mu[c] = np.clip(mun, -1.0, 1.0)
        # tally every new flight (after scattering or surface reflection)
        tally_down(z, mu, w, acc)
        # Russian roulette
        low = w < WMIN
        if np.any(low):
            nl = int(np.count_nonzero(low))
            surv = rng.random(nl) < SURV
            wl = w[low]
            wl = np.where(surv, wl / SURV, 0.0)
            w[low] = wl
        keep = w > 0.0
        if not np.all(keep):
            z, mu, w = z[keep], mu[keep], w[keep]
    return acc * ED_AIR, ncoll


def run_problem(name, w0, pf, n_total, nbatch=10, chunk=1_000_000, seed=12345):
    per = n_total // nbatch
    res = np.zeros((nbatch, len(TAUS)))
    t0 = time.time()
    ncoll = 0
    for b in range(nbatch):
        rng = np.random.default_rng([seed, b])
        acc = np.zeros(len(TAUS))
        done = 0
        while done < per:
            m = min(chunk, per - done)
            a, nc = run_chunk(m, w0, pf, rng)
            acc += a
            ncoll += nc
            done += m
        res[b] = acc / per
        print(f"  {name} batch {b}: {res[b]}  ({time.time()-t0:.0f}s)", flush=True)
    mean = res.mean(axis=0)
    se = res.std(axis=0, ddof=1) / np.sqrt(nbatch)
    return mean, se, time.time() - t0, ncoll / (per * nbatch)


if __name__ == "__main__":
    import json
    job = sys.argv[1]
    n = int(float(sys.argv[2]))
    out = sys.argv[3] if len(sys.argv) > 3 else None
    if job == "pf":
        for d in "AB":
            pf = TabulatedPF(d)
            print(f"def {d}: integral {pf.raw_total:.5f}  bb/b {pf.bb:.5f}  gbar {pf.gbar:.5f}")
        sys.exit()
    prob, defn = job.split(":") if ":" in job else (job, "R")
    w0 = {"1a": 0.9, "2a": 0.9, "2b": 0.2}[prob]
    pf = RayleighPF() if prob.startswith("1") else TabulatedPF(defn)
    mean, se, dt, nc = run_problem(job, w0, pf, n)
    print(job, "Ed", mean, "SE", se, "relSE", se / mean, f"time {dt:.0f}s coll/photon {nc:.1f}")
    if out:
        with open(out, "w") as fh:
            json.dump(dict(job=job, n=n, taus=TAUS.tolist(), Ed=mean.tolist(), SE=se.tolist(),
                           time=dt, coll_per_photon=nc, bb=pf.bb, integral=pf.raw_total,
                           gbar=pf.gbar), fh)
