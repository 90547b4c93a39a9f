#!/usr/bin/env python3
"""Markdown table of canonical-runner results for each photon store, beside M93 Table 5 and
the manual's DIRSIG photon-mapping results (Tables 7.1/7.2). Depth: optical depth tau for
problems 1, 2, 4, 5 and 6, metres for problem 3 (the manual did not score problems 4 and 5: no
DIRSIG value). Problem 4's reported runs under parametric skies are rows of their own
(4/gc-sky, 4/atm-split-sky), marked "rep.". A store's name is its file's: conformance_<store>.json.
The first file sets the rows; later ones may hold some problems only.
usage: conformance_table.py conformance_kdtree.json conformance_voi.json [conformance_voi-grid.json ...]"""
import json
import os
import sys

DIRSIG = {  # manual Tables 7.1 and 7.2 (single maps of up to 1e7 photons)
    ("1a", 1): (3.66e-1, 3.74e-1, 4.88e-2), ("1a", 5): (4.34e-2, 4.30e-2, 5.77e-3), ("1a", 10): (3.14e-3, 3.11e-3, 4.21e-4),
    ("1b", 1): (1.42e-1, 1.33e-2, 1.70e-3), ("1b", 5): (1.06e-3, 9.52e-5, 1.29e-5), ("1b", 10): (2.81e-6, 1.95e-7, 2.81e-8),
    ("2a", 1): (4.13e-1, 9.19e-2, 7.40e-3), ("2a", 5): (1.86e-1, 4.57e-2, 3.05e-3), ("2a", 10): (6.93e-2, 1.66e-2, 8.85e-4),
    ("2b", 1): (1.62e-1, 9.63e-4, 5.33e-5), ("2b", 5): (2.28e-3, 1.17e-5, 7.39e-7), ("2b", 10): (1.29e-5, 6.19e-8, 3.92e-9),
    ("3", 5): (2.13e-1, 4.26e-2, 3.18e-3), ("3", 25): (1.46e-3, 2.54e-4, 1.83e-5), ("3", 60): (3.46e-5, 3.42e-6, 3.84e-7),
    ("6", 1): (1.62e-1, 9.88e-4, 6.90e-5), ("6", 5): (2.29e-3, 2.28e-3, 3.63e-4),
}
QTY = {"Ed": 0, "Eou": 1, "Lu": 2}


NAMES = {"kdtree": "k-d tree", "voi": "VOI octree", "voi-grid": "VOI grid",
         "voi-grid_lanes-float": "VOI grid, float lanes"}


def store_name(path):
    stem = os.path.basename(path)
    stem = stem[len("conformance_"):] if stem.startswith("conformance_") else stem
    stem = stem[:-len(".json")] if stem.endswith(".json") else stem
    return NAMES.get(stem, stem)


def main(paths):
    # Problem 4's reported runs (parametric skies) share the scored run's problem and depth:
    # the light source tells them apart (files without a "source" hold one run per problem).
    label = lambda e: e["problem"] if e.get("scored", True) or not e.get("source") else f'{e["problem"]}/{e["source"]}'
    stores = [{(label(e), e["depth"], e["quantity"]): e for e in json.load(open(p))["entries"]} for p in paths]
    names = [store_name(p) for p in paths]
    # A file may hold some problems only (e.g. the float lanes' 1 and 2): "-" where it has none.
    verdict = lambda e: "-" if e is None else ("pass" if e["pass"] else "FAIL") if e["scored"] else "rep."
    cells = lambda e: "- | -" if e is None else (
        f"{e['value']:.4g} ({100*e['se']/abs(e['value']) if e['value'] else float('inf'):.2f}%) "
        f"| {100*e['relative_error']:+.2f}%")
    print("| problem | depth | qty | M93 mean | s/x | " + " | ".join(f"{n} (SE) | err" for n in names) +
          " | pass " + "/".join(names) + " | DIRSIG | DIRSIG err |")
    print("|---|---|---|---|---|" + "---|---|" * len(names) + "---|---|---|")
    for key, a in stores[0].items():
        entries = [store.get(key) for store in stores]
        dirsig = DIRSIG.get((key[0], int(key[1])))
        d = "- | -" if dirsig is None else (
            f"{dirsig[QTY[key[2]]]:.3g} | {100*(dirsig[QTY[key[2]]]-a['reference'])/a['reference']:+.1f}%")
        print(f"| {key[0]} | {key[1]:g} | {key[2]} | {a['reference']:.3g} | {100*a['spread']:.1f}% | "
              + " | ".join(cells(e) for e in entries)
              + f" | {'/'.join(verdict(e) for e in entries)} | {d} |")


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])
