#!/usr/bin/env python3
"""Seed study of the canonical runner: are its batch standard errors honest? (python3, standard
library only)

    seed_study.py --store voi [--problems all] [--seeds 8] [--threads 2] [--quick] [--out DIR]
    seed_study.py --from DIR [--store voi] [--out DIR]

Runs build/conformance/canonical for seeds 1..K with one store (and tracer), keeps each seed's
JSON (DIR/canonical_<store>_seed<k>.json, its output beside it as .log), and writes
seed_study_<store>.md and seed_study_<store>.json into --out (default build/seed-study). With
--from it runs nothing and aggregates the canonical_<store>_seed<k>.json files in DIR (every
store found there unless --store names one). With --resume, seeds whose JSON exists are not
run again.

Per entry, over the seeds: the mean relative error to the reference; the scatter, the sample
standard deviation of the seeds' values relative to their mean (%); the mean batch SE, the
mean of the seeds' relative standard errors se/value (%); their ratio; and in how many seeds
the entry passes. A scored entry is flagged where the ratio exceeds 1.5 (its SE understates its
error: a defect of the estimator) or where it passes in fewer than K-1 of K seeds. Exit status
1 if any scored entry is flagged. The summary also gives the root mean square of the ratios
(about 1 for honest SEs) and how many entries honest SEs would put above 1.5 by chance (with 8
seeds, 2.75 % of them: the scatter of 8 values is itself uncertain by about a quarter).

At the default (full) budgets a seed takes as long as one store of the main job (a few minutes
on 2 cores), so 8 seeds of each of the three stores take about an hour: it is run apart from
the main job, e.g. for each store
    python3 scripts/seed_study.py --store voi --seeds 8 --threads 2
and add the tables to the conformance report with
    python3 scripts/conformance_report.py build/conformance-results --seed-study build/seed-study/seed_study_voi.json
(a seed_study_*.json inside the report's input directory is added without being named).
"""
import argparse
import glob
import json
import math
import os
import re
import statistics
import subprocess
import sys

from canonical_json import cell, depth_label, entry_key, number, percent

RATIO_LIMIT = 1.5
FILE = re.compile(r"^canonical_(?P<store>.+)_seed(?P<seed>\d+)\.json$")


# ---- aggregation ---------------------------------------------------------------------------

def aggregate(runs):
    """runs: [(seed, parsed canonical JSON)]. One row per entry, in order of first appearance."""
    rows = {}
    for seed, data in runs:
        for e in data.get("entries", []):
            rows.setdefault(entry_key(e), []).append((seed, e))
    out = []
    for key, seen in rows.items():
        first = seen[0][1]
        values = [number(e.get("value")) for _, e in seen]
        rel_se = [number(e.get("se")) / abs(v) if v else math.inf for v, (_, e) in zip(values, seen)]
        errors = [number(e.get("relative_error")) for _, e in seen]
        scored = bool(first.get("scored", True))
        n = len(seen)
        mean = statistics.fmean(values)
        scatter = statistics.stdev(values) / abs(mean) if n >= 2 and mean else math.nan
        mean_se = statistics.fmean(rel_se)
        ratio = scatter / mean_se if mean_se and not math.isnan(scatter) else math.nan
        passes = sum(1 for _, e in seen if e.get("pass"))
        flags = []
        if ratio > RATIO_LIMIT:
            flags.append(f"scatter > {RATIO_LIMIT:g} SE")
        if scored and passes < n - 1:
            flags.append(f"passes < {n - 1}")
        out.append({"problem": key[0], "depth": first.get("depth"), "depth_unit": first.get("depth_unit", ""),
                    "quantity": key[2], "reference": number(first.get("reference")),
                    "spread": number(first.get("spread")), "scored": scored, "seeds": n,
                    "mean_value": mean, "mean_error": statistics.fmean(errors), "scatter": scatter,
                    "mean_se": mean_se, "ratio": ratio, "passes": passes if scored else None,
                    "flagged": scored and bool(flags), "flags": flags})
    return out


def chi2_survival(x, dof):
    """P(X > x) for X chi-square with an integer number of degrees of freedom."""
    if x <= 0:
        return 1.0
    if dof % 2 == 0:
        term, total = 1.0, 1.0
        for i in range(1, dof // 2):
            term *= x / (2 * i)
            total += term
        return math.exp(-x / 2) * total
    total = math.erfc(math.sqrt(x / 2))
    term = math.sqrt(2 * x / math.pi) * math.exp(-x / 2)
    for i in range(1, (dof + 1) // 2):
        total += term
        term *= x / (2 * i + 1)
    return total


def chance_over_limit(seeds):
    """The chance that an entry with an honest SE (normal errors) shows a scatter above
    RATIO_LIMIT times its SE over `seeds` seeds: (K-1) s^2 / sigma^2 is chi-square, K-1 dof."""
    return chi2_survival((seeds - 1) * RATIO_LIMIT ** 2, seeds - 1) if seeds >= 2 else math.nan


def tally(rows):
    scored = [r for r in rows if r["scored"]]
    ratios = [r["ratio"] for r in scored if not (math.isnan(r["ratio"]) or math.isinf(r["ratio"]))]
    return {"scored": len(scored), "flagged": sum(r["flagged"] for r in scored),
            "over_ratio": sum(r["ratio"] > RATIO_LIMIT for r in scored),
            "few_passes": sum(r["passes"] < r["seeds"] - 1 for r in scored),
            "max_ratio": max(ratios, default=math.nan),
            "rms_ratio": math.sqrt(statistics.fmean(q * q for q in ratios)) if ratios else math.nan,
            "expected_over_ratio": sum(chance_over_limit(r["seeds"]) for r in scored)}


def markdown(study):
    """The seed study's table (a list of markdown lines), from its JSON form."""
    rows, seeds = study["entries"], study["seeds"]
    k = len(seeds)
    t = tally(rows)
    lines = [f"Store {study['store']}, seeds {', '.join(str(s) for s in seeds)}"
             + (" (quick budgets)" if study.get("quick") else "") + ". "
             "Scatter: the sample standard deviation of the seeds' values relative to their mean; mean SE: "
             "the mean of the seeds' relative batch standard errors; passes: seeds in which the entry passes. "
             f"Flagged: a scored entry whose scatter exceeds {RATIO_LIMIT:g} times its mean SE, or that passes "
             "in fewer than K-1 of K seeds.", "",
             f"{t['scored'] - t['flagged']} of {t['scored']} scored entries unflagged; "
             f"{t['over_ratio']} with scatter above {RATIO_LIMIT:g} mean SE (largest ratio "
             + ("-" if math.isnan(t["max_ratio"]) else f"{t['max_ratio']:.2f}")
             + f"), {t['few_passes']} passing in fewer than {k - 1} of {k} seeds. "
             "Root mean square of the scored entries' ratios: "
             + ("-" if math.isnan(t["rms_ratio"]) else f"{t['rms_ratio']:.2f}") + " (about 1 where the SEs are "
             f"honest). Even honest SEs exceed the {RATIO_LIMIT:g} limit by chance: with {k} seeds an entry with "
             f"normal errors does so with probability {100 * chance_over_limit(k):.1f}%, so about "
             f"{t['expected_over_ratio']:.1f} of the {t['scored']} scored entries are expected above it.", "",
             "| problem | depth | qty | s/x | mean err | scatter | mean SE | scatter/SE | passes | flag |",
             "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        ratio = "-" if math.isnan(r["ratio"]) else f"{r['ratio']:.2f}"
        passes = "reported" if r["passes"] is None else f"{r['passes']}/{r['seeds']}"
        flag = "**" + ", ".join(r["flags"]) + "**" if r["flagged"] else ""
        lines.append(f"| {cell(r['problem'])} | {cell(depth_label(r))} | {cell(r['quantity'])} | "
                     f"{percent(r['spread'], False, 1)} | {percent(r['mean_error'], True)} | "
                     f"{percent(r['scatter'], False)} | {percent(r['mean_se'], False)} | "
                     f"{ratio} | {passes} | {flag} |")
    return lines


def study_of(store, runs, quick=None):
    runs = sorted(runs, key=lambda r: r[0])
    return {"store": store, "seeds": [s for s, _ in runs], "quick": quick, "ratio_limit": RATIO_LIMIT,
            "entries": aggregate(runs)}


def clean(x):
    """nan and inf as null: the JSON stays standard."""
    if isinstance(x, float) and (math.isnan(x) or math.isinf(x)):
        return None
    if isinstance(x, dict):
        return {k: clean(v) for k, v in x.items()}
    if isinstance(x, list):
        return [clean(v) for v in x]
    return x


def write_study(study, out):
    """seed_study_<store>.md and .json into `out`; returns the two paths."""
    os.makedirs(out, exist_ok=True)
    stem = os.path.join(out, "seed_study_" + re.sub(r"[^A-Za-z0-9_.-]", "_", study["store"]))
    with open(stem + ".md", "w") as f:
        f.write(f"# Seed study: {study['store']}\n\n" + "\n".join(markdown(study)) + "\n")
    with open(stem + ".json", "w") as f:
        json.dump(clean(study), f, indent=1)
        f.write("\n")
    return stem + ".md", stem + ".json"


def load_study(path):
    """A seed_study_<store>.json back, its nulls as nan."""
    with open(path) as f:
        study = json.load(f)
    for r in study["entries"]:
        for k in ("reference", "spread", "mean_value", "mean_error", "scatter", "mean_se", "ratio"):
            r[k] = number(r.get(k))
    return study


def read_seed_files(directory, store=None):
    """{store: [(seed, parsed JSON)]} from DIR/canonical_<store>_seed<k>.json."""
    found = {}
    for path in sorted(glob.glob(os.path.join(directory, "canonical_*_seed*.json"))):
        m = FILE.match(os.path.basename(path))
        if m is None or (store is not None and m["store"] != store):
            continue
        with open(path) as f:
            found.setdefault(m["store"], []).append((int(m["seed"]), json.load(f)))
    return found


# ---- running -------------------------------------------------------------------------------

def run_seeds(args, label):
    """canonical once per seed; a seed's JSON and log in args.out."""
    os.makedirs(args.out, exist_ok=True)
    for seed in range(1, args.seeds + 1):
        path = os.path.join(args.out, f"canonical_{label}_seed{seed}.json")
        if args.resume and os.path.exists(path):
            print(f"seed {seed}: kept {path}")
            continue
        cmd = [args.canonical, "--problem", args.problems, "--seed", str(seed), "--threads", str(args.threads),
               "--json", path]
        # The store, and the outputs of problems 2a and 3, where the study runs problems they
        # change (canonical refuses an option that changes none of the problems it runs: Kirk's
        # runs build no photon map).
        chosen = args.problems.split(",")
        if any(p != "kirk" for p in chosen):
            cmd += ["--store", args.store]
        if "all" in chosen or "2a" in chosen:
            cmd += ["--exr", os.path.join(args.out, f"photon_map_2a_{label}.exr")]
        if "all" in chosen or "3" in chosen:
            cmd += ["--profile-csv", os.path.join(args.out, "iop_profile_3.csv")]
        if args.tracer:
            cmd += ["--tracer", args.tracer]
        if args.quick:
            cmd.append("--quick")
        print(f"seed {seed}: " + " ".join(cmd), flush=True)
        with open(path[:-len(".json")] + ".log", "w") as log:
            status = subprocess.run(cmd, stdout=log, stderr=subprocess.STDOUT).returncode
        # Status 1 is canonical's "some entry failed": the study counts it; anything else is an error.
        if status not in (0, 1) or not os.path.exists(path):
            sys.exit(f"seed_study.py: canonical exited with status {status} (see {path[:-5]}.log)")


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--store", help="kdtree, voi or voi-grid (with --from: the store to aggregate; default all found)")
    parser.add_argument("--problems", default="all", help="canonical --problem: all, or a list such as 1a,2b,3")
    parser.add_argument("--seeds", type=int, default=8, help="seeds 1..K (default 8)")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--tracer", help="canonical --tracer (photon, lanes, lanes-float)")
    parser.add_argument("--quick", action="store_true",
                        help="canonical --quick (budgets / 5); with --from, marks the study as one of quick budgets")
    parser.add_argument("--resume", action="store_true", help="keep the seeds whose JSON exists")
    parser.add_argument("--canonical", default=os.path.join(root, "build", "conformance", "canonical"))
    parser.add_argument("--out", default=os.path.join(root, "build", "seed-study"))
    parser.add_argument("--from", dest="source", metavar="DIR", help="aggregate DIR's seed files, run nothing")
    args = parser.parse_args(argv)
    quick = args.quick
    if args.source is None:
        if not args.store:
            parser.error("--store is required unless --from is given")
        if args.seeds < 2:
            parser.error("--seeds must be at least 2 (the scatter is a sample standard deviation)")
        label = args.store + (f"_{args.tracer}" if args.tracer and args.tracer != "photon" else "")
        run_seeds(args, label)
        found = read_seed_files(args.out, label)
        found[label] = [r for r in found.get(label, []) if r[0] <= args.seeds]
    else:
        found = read_seed_files(args.source, args.store)
        if not found:
            sys.exit(f"seed_study.py: no canonical_<store>_seed<k>.json in {args.source}")
    flagged = 0
    for store, runs in found.items():
        study = study_of(store, runs, quick)
        md, js = write_study(study, args.out)
        t = tally(study["entries"])
        flagged += t["flagged"]
        print(f"{store}: {len(runs)} seeds, {t['scored'] - t['flagged']} of {t['scored']} scored entries unflagged; "
              f"{md}, {js}")
    return 1 if flagged else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
