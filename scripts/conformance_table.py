#!/usr/bin/env python3
"""Markdown table of canonical-runner results for both stores, beside M93 Table 5 and the
manual's DIRSIG photon-mapping results (Tables 7.1/7.2). Depth: optical depth tau for
problems 1 and 2, metres for problem 3.
usage: conformance_table.py conformance_kdtree.json conformance_voi.json"""
import json
import sys

DIRSIG = {  # manual Tables 7.1 and 7.2 (single maps of up to 1e7 photons)
    ("1a", 1): (3.66e-1, 3.74e-1, 4.88e-2), ("1a", 5): (4.34e-2, 4.30e-2, 5.77e-3), ("1a", 10): (3.14e-3, 3.11e-3, 4.21e-4),
    ("1b", 1): (1.42e-1, 1.33e-2, 1.70e-3), ("1b", 5): (1.06e-3, 9.52e-5, 1.29e-5), ("1b", 10): (2.81e-6, 1.95e-7, 2.81e-8),
    ("2a", 1): (4.13e-1, 9.19e-2, 7.40e-3), ("2a", 5): (1.86e-1, 4.57e-2, 3.05e-3), ("2a", 10): (6.93e-2, 1.66e-2, 8.85e-4),
    ("2b", 1): (1.62e-1, 9.63e-4, 5.33e-5), ("2b", 5): (2.28e-3, 1.17e-5, 7.39e-7), ("2b", 10): (1.29e-5, 6.19e-8, 3.92e-9),
    ("3", 5): (2.13e-1, 4.26e-2, 3.18e-3), ("3", 25): (1.46e-3, 2.54e-4, 1.83e-5), ("3", 60): (3.46e-5, 3.42e-6, 3.84e-7),
}
QTY = {"Ed": 0, "Eou": 1, "Lu": 2}


def main(kd_path, voi_path):
    kd = {(e["problem"], e["depth"], e["quantity"]): e for e in json.load(open(kd_path))["entries"]}
    voi = {(e["problem"], e["depth"], e["quantity"]): e for e in json.load(open(voi_path))["entries"]}
    print("| problem | depth | qty | M93 mean | s/x | k-d tree (SE) | err | VOI (SE) | err | pass kd/voi | DIRSIG | DIRSIG err |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for key, a in kd.items():
        b = voi[key]
        d = DIRSIG[(key[0], int(key[1]))][QTY[key[2]]]
        verdict = lambda e: ("pass" if e["pass"] else "FAIL") if e["scored"] else "rep."
        print(f"| {key[0]} | {key[1]:g} | {key[2]} | {a['reference']:.3g} | {100*a['spread']:.1f}% "
              f"| {a['value']:.4g} ({100*a['se']/abs(a['value']) if a['value'] else float('inf'):.2f}%) | {100*a['relative_error']:+.2f}% "
              f"| {b['value']:.4g} ({100*b['se']/abs(b['value']) if b['value'] else float('inf'):.2f}%) | {100*b['relative_error']:+.2f}% "
              f"| {verdict(a)}/{verdict(b)} | {d:.3g} | {100*(d-a['reference'])/a['reference']:+.1f}% |")


if __name__ == "__main__":
    main(*sys.argv[1:3])
