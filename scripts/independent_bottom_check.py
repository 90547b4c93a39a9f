#!/usr/bin/env python3
"""A cross-check of canonical problem 6 that shares no code with secchi (numpy only; not part
of the tests): the nadir radiance at tau 1 due to the light leaving the Lambertian bottom at
tau 5 (water c = 1 /m, w0 = 0.2, the Petzold function of canonical_problems.md, definition A
of independent_ed_check.py). Per unit bottom radiance L_b it prints
  - the direct part e^-4,
  - single scattering by deterministic quadrature:
      b int_0^4 ds e^-s int 2 pi p(psi) sin(psi) e^-(4 - s)/cos(psi) dpsi,
  - all orders by Monte Carlo: photons leave the bottom (cosine-weighted), scatter (analog,
    w0), and each scattering event below tau 1 adds p(angle to the vertical) e^-(z - 1);
    photons that return to the bottom stop (the measured Ed on the bottom already holds them).
The Monte Carlo tally is heavy-tailed (p grows as psi^-1.346 towards the forward direction),
so its batch standard error understates its spread: compare seeds. Usage:
    python3 scripts/independent_bottom_check.py [SEED] [PHOTONS] [ED_BOTTOM]
"""
import sys

import numpy as np

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from independent_ed_check import TabulatedPF, read_table  # noqa: E402

PF = TabulatedPF("A")
ANG, P = read_table()
PSI_N = np.radians(ANG)
F_NODES = 2 * np.pi * P * np.sin(PSI_N) / PF.raw_total  # normalised 2 pi p sin(psi), linear in psi


def p_of(psi):
    """The normalised phase function (1/sr): power law below the first node, else from f."""
    psi = np.asarray(psi, dtype=float)
    out = np.empty_like(psi)
    lo = psi < PSI_N[0]
    out[lo] = P[0] / PF.raw_total * (PSI_N[0] / np.maximum(psi[lo], 1e-300)) ** 1.346
    hi = ~lo
    out[hi] = np.interp(psi[hi], PSI_N, F_NODES) / (2 * np.pi * np.sin(psi[hi]))
    return out


def single_scattering(b=0.2, height=4.0):
    psi = np.concatenate([np.logspace(-9, np.log10(PSI_N[0]), 4000, endpoint=False),
                          np.linspace(PSI_N[0], np.pi / 2 - 1e-9, 400000)])
    s = np.linspace(0.0, height, 4001)
    f = 2 * np.pi * p_of(psi) * np.sin(psi)
    inner = np.array([np.trapezoid(f * np.exp(-(height - si) / np.cos(psi)), psi) for si in s])
    inner += f[0] * psi[0] / 0.654 * np.exp(-(height - s))  # psi below 1e-9: f ~ psi^-0.346
    return b * np.trapezoid(np.exp(-s) * inner, s)


def rotate(d, c, sn, ph):
    sign = np.where(d[:, 2] >= 0, 1.0, -1.0)
    a = -1.0 / (sign + d[:, 2])
    bq = d[:, 0] * d[:, 1] * a
    e1 = np.stack([1 + sign * d[:, 0] ** 2 * a, sign * bq, -sign * d[:, 0]], axis=1)
    e2 = np.stack([bq, sign + d[:, 1] ** 2 * a, -d[:, 1]], axis=1)
    out = (sn * np.cos(ph))[:, None] * e1 + (sn * np.sin(ph))[:, None] * e2 + c[:, None] * d
    return out / np.linalg.norm(out, axis=1)[:, None]


def all_orders(rng, photons, w0=0.2, bottom=5.0, detector=1.0, batches=10):
    values = []
    for _ in range(batches):
        n = photons // batches
        mu = np.sqrt(rng.random(n))
        phi = 2 * np.pi * rng.random(n)
        st = np.sqrt(1 - mu * mu)
        d = np.stack([st * np.cos(phi), st * np.sin(phi), -mu], axis=1)  # z down: up is -z
        z = np.full(n, bottom)
        alive = np.ones(n, bool)
        tally = 0.0
        while alive.any():
            idx = np.nonzero(alive)[0]
            znew = z[idx] + d[idx, 2] * -np.log(rng.random(idx.size))
            out = (znew < 0.0) | (znew > bottom)
            alive[idx[out]] = False
            keep = idx[~out]
            z[keep] = znew[~out]
            scatter = rng.random(keep.size) < w0
            alive[keep[~scatter]] = False
            keep = keep[scatter]
            seen = keep[z[keep] > detector]
            tally += np.sum(p_of(np.arccos(np.clip(-d[seen, 2], -1, 1))) * np.exp(-(z[seen] - detector)))
            c, sn = PF.sample_cos(rng, keep.size)
            d[keep] = rotate(d[keep], c, sn, 2 * np.pi * rng.random(keep.size))
        values.append(tally * np.pi / n)  # n photons leave unit area carrying pi L_b
    v = np.array(values)
    return v.mean(), v.std(ddof=1) / np.sqrt(len(v))


def main():
    seed = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    photons = int(float(sys.argv[2])) if len(sys.argv) > 2 else 4_000_000
    ed_bottom = float(sys.argv[3]) if len(sys.argv) > 3 else 2.2869e-3  # secchi's, seed 1
    lb = 0.5 * ed_bottom / np.pi
    direct, single = np.exp(-4.0), single_scattering()
    mc, se = all_orders(np.random.default_rng(seed), photons)
    print(f"per unit L_b: direct {direct:.5e}, single scattering {single:.5e}, all orders (MC) {mc:.5e} +- {se:.1e}")
    print(f"L_b = 0.5 Ed / pi with Ed = {ed_bottom:.5g}: direct {lb*direct:.4e}, single {lb*single:.4e}, "
          f"all orders {lb*mc:.4e}, total {lb*(direct+mc):.4e} (M93 6 - 2b at tau 1: 1.37e-5)")


if __name__ == "__main__":
    main()
