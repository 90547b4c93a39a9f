#!/usr/bin/env python3
"""Conformance report of the canonical runner (conformance/canonical.cpp): a markdown table per
problem and one SVG figure per problem (python3, standard library only).

    conformance_report.py [--out DIR] [--seed-study FILE.json ...] DIR
    conformance_report.py [--out DIR] [--seed-study FILE.json ...] conformance_kdtree.json conformance_voi.json ...

Input: the JSON files of `canonical --json`, one per photon store (or tracer, or material
run); a store's name is its file's, conformance_<store>.json. Given a directory, every
conformance_*.json in it is read, and every seed_study_*.json (scripts/seed_study.py) is added
as the seed-study section. A file may hold some problems only; a problem's table and figure
show the files that hold it.

Output (into --out, by default the directory of the input): conformance_report.md and
conformance_<problem>.svg.

The table of a problem: depth, quantity, the reference (M93 Table 5 mean, or Kirk's relation
for a "kirk" problem) and its spread s/x, then per store our value with its relative standard
error and our relative error to the printed reference, each store's verdict (pass, FAIL, or
"reported" for an entry that is not scored), and the manual's DIRSIG photon-mapping value
(Tables 7.1 and 7.2) with its relative error to the M93 mean.

The figure of a problem, in the style of the manual's Figures 7.28-7.35: a row per quantity
(Ed, Eou, Lu). Left, the values against depth on a log scale: the reference at each depth with
its spread, mean (1 +- s/x), as a grey box (a dashed line joins the means), ours per store with
+-2 SE error bars (the stores set slightly apart in depth; an open dot for an entry that is not
scored), DIRSIG's value as an open diamond.
Right, the same as relative errors to the reference in percent, where the spread and the error
bars can be told apart.
"""
import argparse
import glob
import json
import math
import os
import re
import sys
from xml.sax.saxutils import escape

import seed_study
from canonical_json import cell, depth_label, entry_key, number, percent

# The manual's DIRSIG photon-mapping results (Tables 7.1 and 7.2, single maps of up to 1e7
# photons): (problem, depth) -> (Ed, Eou, Lu). Problems 4 and 5 were not scored there.
DIRSIG = {
    ("1a", 1): (3.66e-1, 3.74e-1, 4.88e-2), ("1a", 5): (4.34e-2, 4.30e-2, 5.77e-3), ("1a", 10): (3.14e-3, 3.11e-3, 4.21e-4),
    ("1b", 1): (1.42e-1, 1.33e-2, 1.70e-3), ("1b", 5): (1.06e-3, 9.52e-5, 1.29e-5), ("1b", 10): (2.81e-6, 1.95e-7, 2.81e-8),
    ("2a", 1): (4.13e-1, 9.19e-2, 7.40e-3), ("2a", 5): (1.86e-1, 4.57e-2, 3.05e-3), ("2a", 10): (6.93e-2, 1.66e-2, 8.85e-4),
    ("2b", 1): (1.62e-1, 9.63e-4, 5.33e-5), ("2b", 5): (2.28e-3, 1.17e-5, 7.39e-7), ("2b", 10): (1.29e-5, 6.19e-8, 3.92e-9),
    ("3", 5): (2.13e-1, 4.26e-2, 3.18e-3), ("3", 25): (1.46e-3, 2.54e-4, 1.83e-5), ("3", 60): (3.46e-5, 3.42e-6, 3.84e-7),
    ("6", 1): (1.62e-1, 9.88e-4, 6.90e-5), ("6", 5): (2.29e-3, 2.28e-3, 3.63e-4),
}
DIRSIG_QUANTITIES = ("Ed", "Eou", "Lu")

STORE_NAMES = {"kdtree": "k-d tree", "voi": "VOI octree", "voi-grid": "VOI grid",
               "voi-grid_lanes-float": "VOI grid, float lanes", "3_material": "VOI octree, material file"}
STORE_ORDER = list(STORE_NAMES)

TITLES = {"1a": "Rayleigh phase function, w0 = 0.9", "1b": "Rayleigh phase function, w0 = 0.2",
          "2a": "Petzold particle phase function, w0 = 0.9", "2b": "Petzold particle phase function, w0 = 0.2",
          "3": "stratified water (chlorophyll profile), 500 nm", "4": "as 2a, with an atmosphere",
          "5": "as 2a, sun at 80 deg, wind-blown surface", "6": "as 2b, Lambertian bottom of reflectance 0.5 at tau 5"}

UNITS = {"Ed": "W m-2 nm-1", "Eou": "W m-2 nm-1", "Lu": "W m-2 nm-1 sr-1"}
COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#ff7f0e", "#9467bd", "#8c564b", "#17becf", "#e377c2"]


# ---- reading -------------------------------------------------------------------------------

def is_kirk(problem):
    return str(problem).lower().startswith("kirk")


class Run:
    """One JSON file of the canonical runner: its store's name and its entries by key."""

    def __init__(self, path):
        self.path = path
        self.stem = store_stem(path)
        self.name = STORE_NAMES.get(self.stem, self.stem)
        with open(path) as f:
            data = json.load(f)
        self.seconds = number(data.get("seconds"))
        self.entries = {}
        for e in data.get("entries", []):
            self.entries[entry_key(e)] = e


def store_stem(path):
    """conformance_<store>.json -> <store>."""
    stem = os.path.basename(path)
    stem = stem[len("conformance_"):] if stem.startswith("conformance_") else stem
    return stem[:-len(".json")] if stem.endswith(".json") else stem


def order_runs(paths):
    """The known stores first, in their usual order, then the others by name."""
    def rank(path):
        stem = store_stem(path)
        return (STORE_ORDER.index(stem) if stem in STORE_ORDER else len(STORE_ORDER), stem)
    return sorted(paths, key=rank)


def rows_by_problem(runs):
    """Problem -> its entry keys, both in order of first appearance over the runs."""
    problems = {}
    for run in runs:
        for key in run.entries:
            keys = problems.setdefault(key[0], [])
            if key not in keys:
                keys.append(key)
    return problems


# ---- numbers and cells ---------------------------------------------------------------------

def sci(v, digits=3):
    """3.66e-1 style (M93's notation): `digits` significant digits, a short exponent."""
    if math.isnan(v):
        return "-"
    if v == 0:
        return "0"
    mantissa, exponent = f"{v:.{digits - 1}e}".split("e")
    return f"{mantissa}e{int(exponent)}"


def relative_se(e):
    value, se = number(e.get("value")), number(e.get("se"))
    return se / abs(value) if value else math.inf


def verdict(e):
    if e is None:
        return "-"
    if e.get("blocked"):
        return "blocked"
    if not e.get("scored", True):
        return "reported"
    return "pass" if e.get("pass") else "FAIL"


def dirsig_value(key):
    """The manual's DIRSIG value of an entry, or None (1.0 finds the key 1)."""
    problem, depth, quantity = key
    values = DIRSIG.get((problem, depth))
    if values is None or quantity not in DIRSIG_QUANTITIES:
        return None
    return values[DIRSIG_QUANTITIES.index(quantity)]


# ---- markdown ------------------------------------------------------------------------------

def problem_table(problem, keys, runs):
    """Markdown table of one problem: a row per entry, column pairs per run that holds it."""
    held = [r for r in runs if any(k in r.entries for k in keys)]
    ref = "Kirk's relation" if is_kirk(problem) else "M93 mean"
    lines = ["| depth | qty | " + ref + " | s/x | " + " | ".join(f"{r.name} (SE) | err" for r in held)
             + " | pass | DIRSIG | DIRSIG err |",
             "|---|---|---|---|" + "---|---|" * len(held) + "---|---|---|"]
    for key in keys:
        entries = [r.entries.get(key) for r in held]
        first = next(e for e in entries if e is not None)
        reference, spread = number(first.get("reference")), number(first.get("spread"))
        cells = []
        for e in entries:
            if e is None:
                cells.append("- | -")
            else:
                cells.append(f"{sci(number(e.get('value')), 4)} ({percent(relative_se(e), signed=False)}) | "
                             f"{percent(number(e.get('relative_error')), True)}")
        d = dirsig_value(key)
        dirsig = "- | -" if d is None or not reference else f"{sci(d)} | {percent((d - reference) / reference, True, 1)}"
        lines.append(f"| {cell(depth_label(first))} | {cell(key[2])} | {sci(reference)} | {percent(spread, False, 1)} | "
                     + " | ".join(cells) + f" | {'/'.join(verdict(e) for e in entries)} | {dirsig} |")
    return lines


def tally(run, problems=None):
    """(passing, scored, reported only) over the run's entries, of the given problems."""
    chosen = [e for k, e in run.entries.items() if problems is None or k[0] in problems]
    scored = [e for e in chosen if e.get("scored", True)]
    return sum(1 for e in scored if e.get("pass")), len(scored), len(chosen) - len(scored)


def summary(runs, problems):
    m93 = [p for p in problems if not is_kirk(p)]
    kirk = [p for p in problems if is_kirk(p)]
    lines = ["| store | seconds | " + " | ".join(cell(p) for p in problems) + " | scored entries passing |",
             "|---|---|" + "---|" * len(problems) + "---|"]
    for run in runs:
        cells = []
        for p in problems:
            passing, scored, reported = tally(run, [p])
            text = "-" if scored + reported == 0 else f"{passing}/{scored}"
            cells.append(text + (f" (+{reported} rep.)" if reported else ""))
        passing, scored, _ = tally(run)
        seconds = "-" if math.isnan(run.seconds) else f"{run.seconds:.0f}"
        lines.append(f"| {run.name} | {seconds} | " + " | ".join(cells) + f" | {passing} of {scored} |")
    lines.append("")
    for run in runs:
        parts = []
        for label, chosen in (("M93", m93), ("Kirk", kirk)):
            passing, scored, reported = tally(run, chosen)
            if scored + reported == 0:
                continue
            text = f"{passing} of {scored} scored {label} entries pass"
            parts.append(text + (f", {reported} reported only" if reported else ""))
        failing = [f"{k[0]} {depth_label(e)} {k[2]}" for k, e in run.entries.items()
                   if e.get("scored", True) and not e.get("pass")]
        if failing:
            parts.append("failing: " + ", ".join(cell(f) for f in failing))
        lines.append(f"- {run.name} (`{os.path.basename(run.path)}`): " + "; ".join(parts) + ".")
    return lines


def problem_title(problem):
    if is_kirk(problem):
        return "Kirk's relations" + ("" if problem.lower() == "kirk" else f" ({problem})")
    base, _, source = problem.partition("/")
    title = f"Problem {base}" + (f": {TITLES[base]}" if base in TITLES else "")
    return title + (f", under {source} (reported beside the scored run)" if source else "")


def svg_name(problem):
    return "conformance_" + re.sub(r"[^A-Za-z0-9_.-]", "_", problem) + ".svg"


def report(runs, studies):
    problems = rows_by_problem(runs)
    lines = ["# Conformance report", "",
             "The canonical problems of Mobley et al. 1993 (M93) solved by `conformance/canonical` with each "
             "photon store, against the M93 Table 5 mean and its model spread s/x, and beside the DIRSIG "
             "photon-mapping results of the manual (Tables 7.1 and 7.2). Depth: optical depth tau, or metres "
             "(problem 3). Per store: our value with its relative standard error (SE), and err, our relative "
             "error to the printed reference. The verdicts are the runner's: a scored entry passes when its "
             "error to the interval the printed mean stands for is within max(s/x, 3 SE) and its SE within "
             "max(s/x, 0.5 %) (with --quick: within max(s/x, 4 SE)); \"reported\" entries are shown, not scored, "
             "and \"blocked\" ones wait for the specification (their reasons are listed at the end). "
             "The pass column gives the stores' verdicts in the table's order. "
             "DIRSIG err is the manual's value relative to the M93 mean.", "",
             "## Summary", ""] + summary(runs, list(problems))
    for problem, keys in problems.items():
        lines += ["", f"## {escape(problem_title(problem))}", ""]
        if is_kirk(problem):
            lines += ["The reference is Kirk's relation (canonical_problems.md section 7), not M93.", ""]
        lines += [f"![problem {escape(problem)}]({svg_name(problem)})", ""] + problem_table(problem, keys, runs)
    blocked = {(e.get("problem"), e.get("depth"), e.get("quantity")): e.get("blocked")
               for run in runs for e in run.entries.values() if e.get("blocked")}
    if blocked:
        lines += ["", "## Blocked entries", "",
                  "Entries whose verdict hangs on a question the specification (canonical_problems.md) leaves "
                  "open: reported, not scored, until it answers.", ""]
        lines += [f"- problem {cell(p)}, depth {cell(d)}, {cell(q)}: {cell(why)}" for (p, d, q), why in sorted(
            blocked.items(), key=lambda kv: tuple(str(x) for x in kv[0]))]
    for path, study in studies:
        table = seed_study.markdown(study)
        store = str(study.get("store", ""))
        lines += ["", f"## Seed study: {cell(STORE_NAMES.get(store, store))}", "",
                  f"From `{os.path.basename(path)}`. " + table[0]] + table[1:]
    return "\n".join(lines) + "\n"


# ---- SVG -----------------------------------------------------------------------------------

def svg_line(x1, y1, x2, y2, stroke, width=1.0, dash=None):
    style = f' stroke-dasharray="{dash}"' if dash else ""
    return (f'<line x1="{x1:.1f}" y1="{y1:.1f}" x2="{x2:.1f}" y2="{y2:.1f}" stroke="{stroke}" '
            f'stroke-width="{width:g}"{style}/>')


def svg_text(x, y, text, size, anchor="middle", rotate=False):
    place = f'transform="translate({x:.1f},{y:.1f}) rotate(-90)"' if rotate else f'x="{x:.1f}" y="{y:.1f}"'
    return f'<text {place} text-anchor="{anchor}" font-size="{size}">{escape(str(text))}</text>'


def svg_circle(x, y, fill, stroke):
    return f'<circle cx="{x:.1f}" cy="{y:.1f}" r="3" fill="{fill}" stroke="{stroke}" stroke-width="1.2"/>'


def svg_diamond(x, y):
    return (f'<polygon points="{x:.1f},{y - 5:.1f} {x + 5:.1f},{y:.1f} {x:.1f},{y + 5:.1f} {x - 5:.1f},{y:.1f}" '
            'fill="white" stroke="black" stroke-width="1.3"/>')


def nice_step(span, target):
    raw = span / target
    magnitude = 10 ** math.floor(math.log10(raw))
    for m in (1, 2, 2.5, 5, 10):
        if raw <= m * magnitude:
            return m * magnitude
    return 10 * magnitude


def linear_ticks(lo, hi, target=5):
    step = nice_step(hi - lo, target)
    ticks, t = [], math.ceil(lo / step - 1e-9) * step
    while t <= hi + 1e-9 * step:
        ticks.append(0.0 if abs(t) < 1e-12 * step else t)
        t += step
    return ticks


class DepthAxis:
    """Depth across a panel: linear from 0 (or the least depth) for numeric depths, evenly
    spaced labels otherwise."""

    def __init__(self, depths):
        self.numeric = all(isinstance(d, float) for d in depths)
        if self.numeric:
            lo, hi = min(0.0, min(depths)), max(depths)
            hi = lo + 1.12 * (hi - lo) if hi > lo else lo + 1  # room for the markers beside the last depth
            self.ticks = linear_ticks(lo, hi, 6)
            self.lo, self.hi = min(lo, self.ticks[0]), max(hi, self.ticks[-1])
        else:
            self.labels = list(dict.fromkeys(depths))

    def fraction(self, d):
        if self.numeric:
            return (d - self.lo) / (self.hi - self.lo)
        return (self.labels.index(d) + 0.5) / len(self.labels)

    def tick_marks(self):
        if self.numeric:
            return [(self.fraction(t), f"{t:g}") for t in self.ticks]
        return [(self.fraction(d), str(d)) for d in self.labels]


class Panel:
    """A rectangle with a depth axis across and a value axis (log or linear) up."""

    def __init__(self, x0, y0, w, h, axis, lo, hi, log):
        self.x0, self.y0, self.w, self.h, self.axis, self.log = x0, y0, w, h, axis, log
        if log:
            self.lo, self.hi = math.floor(math.log10(lo)), math.ceil(math.log10(hi))
            if self.hi <= self.lo:
                self.hi = self.lo + 1
        else:
            self.ticks = linear_ticks(lo, hi)
            self.lo, self.hi = min(lo, self.ticks[0]), max(hi, self.ticks[-1])
        self.parts = []

    def px(self, depth, offset=0.0):
        return self.x0 + self.w * self.axis.fraction(depth) + offset

    def py(self, v):
        """Clamped to the panel (a log axis sends non-positive values to its bottom)."""
        if self.log:
            t = (math.log10(v) - self.lo) / (self.hi - self.lo) if v > 0 else -1.0
        else:
            t = (v - self.lo) / (self.hi - self.lo)
        return self.y0 + self.h * (1 - min(1.0, max(0.0, t)))

    def frame(self, title, ylabel, xlabel):
        p, x0, y0, x1, y1 = self.parts, self.x0, self.y0, self.x0 + self.w, self.y0 + self.h
        if self.log:
            # Decades; within a span of two decades or less, 2 and 5 times them too.
            steps = (1, 2, 5) if self.hi - self.lo <= 2 else (1,)
            ys = [(self.py(m * 10.0 ** e), f"{m}e{e}") for e in range(self.lo, self.hi + 1) for m in steps
                  if m == 1 or e < self.hi]
        else:
            ys = [(self.py(t), f"{t:g}") for t in self.ticks]
        for y, label in ys:
            p += [svg_line(x0, y, x1, y, "#e4e4e4"), svg_text(x0 - 5, y + 4, label, 10, "end")]
        for f, label in self.axis.tick_marks():
            x = x0 + self.w * f
            p += [svg_line(x, y0, x, y1, "#e4e4e4"), svg_text(x, y1 + 14, label, 10)]
        p.append(f'<rect x="{x0}" y="{y0}" width="{self.w}" height="{self.h}" fill="none" stroke="#333"/>')
        p += [svg_text(x0 + self.w / 2, y0 - 7, title, 12), svg_text(x0 + self.w / 2, y1 + 30, xlabel, 11),
              svg_text(x0 - 44, y0 + self.h / 2, ylabel, 11, rotate=True)]

    def across(self, depth, half_width):
        """From - to + half_width pixels about a depth, within the panel."""
        x = self.px(depth)
        return max(self.x0, x - half_width), min(self.x0 + self.w, x + half_width)

    def spread_box(self, depth, low, high, half_width):
        """The reference's spread at one depth: a grey box across the depth's markers."""
        (xa, xb), y_lo, y_hi = self.across(depth, half_width), self.py(low), self.py(high)
        self.parts.append(f'<rect x="{xa:.1f}" y="{y_hi:.1f}" width="{xb - xa:.1f}" '
                          f'height="{max(y_lo - y_hi, 1.0):.1f}" fill="#bbb" fill-opacity="0.55"/>')

    def reference_line(self, depths, values, half_width):
        """The reference: dashed through the depths, a solid tick across each depth's markers."""
        pts = " ".join(f"{self.px(d):.1f},{self.py(v):.1f}" for d, v in zip(depths, values))
        self.parts.append(f'<polyline points="{pts}" fill="none" stroke="#555" stroke-width="1" stroke-dasharray="5,3"/>')
        for d, v in zip(depths, values):
            (xa, xb), y = self.across(d, half_width), self.py(v)
            self.parts.append(svg_line(xa, y, xb, y, "#555", 1.5))

    def point(self, depth, offset, value, low, high, colour, scored=True):
        """Ours with its error bar: a filled dot, or an open one for an entry not scored."""
        x = self.px(depth, offset)
        y, y_lo, y_hi = self.py(value), self.py(low), self.py(high)
        self.parts += [svg_line(x, y_lo, x, y_hi, colour, 1.5), svg_line(x - 3, y_lo, x + 3, y_lo, colour, 1.5),
                       svg_line(x - 3, y_hi, x + 3, y_hi, colour, 1.5),
                       svg_circle(x, y, colour if scored else "white", colour)]

    def diamond(self, depth, offset, value):
        self.parts.append(svg_diamond(self.px(depth, offset), self.py(value)))


def quantity_series(quantity, keys, runs):
    """The rows of one quantity: (depth, reference, spread, DIRSIG's value, [entry or None per run])."""
    series = []
    for key in keys:
        if key[2] != quantity:
            continue
        entries = [r.entries.get(key) for r in runs]
        first = next(e for e in entries if e is not None)
        series.append((key[1], number(first.get("reference")), number(first.get("spread")), dirsig_value(key), entries))
    return series


def finite(values):
    return [v for v in values if not (math.isnan(v) or math.isinf(v))]


def value_range(series):
    """(lo, hi, log) of a value panel: log where there are positive values (a zero estimate then
    sits on the panel's bottom), linear where there is a negative one."""
    vals = [s[1] for s in series] + [s[3] for s in series if s[3] is not None]
    vals += [number(e.get("value")) for s in series for e in s[4] if e is not None]
    vals = finite(vals)
    positive = [v for v in vals if v > 0]
    log = bool(positive) and all(v >= 0 for v in vals)
    lo, hi = (min(positive), max(positive)) if log else (min(vals + [0.0]), max(vals + [1.0]))
    if lo == hi:
        lo, hi = lo - abs(lo) * 0.5 - 1e-12, hi + abs(hi) * 0.5 + 1e-12
    return lo, hi, log


def error_range(series):
    """Half the height of a relative-error panel, in percent: every spread, error bar and
    DIRSIG marker inside, at least 1 %."""
    errs = [1.0]
    for depth, reference, spread, dirsig, entries in series:
        if math.isnan(reference) or not reference:
            continue
        errs.append(100 * spread)
        if dirsig is not None:
            errs.append(100 * abs(dirsig - reference) / abs(reference))
        for e in entries:
            if e is not None:
                v, se = number(e.get("value")), number(e.get("se"))
                errs.append(100 * (abs(v - reference) + 2 * (0.0 if math.isnan(se) else se)) / abs(reference))
    return 1.08 * max(finite(errs))


def figure(problem, keys, runs):
    """The SVG of one problem: per quantity a value panel and a relative-error panel."""
    held = [r for r in runs if any(k in r.entries for k in keys)]
    colours = [COLOURS[runs.index(r) % len(COLOURS)] for r in held]  # a store's colour in every figure
    quantities = list(dict.fromkeys(k[2] for k in keys))
    unit = next(r.entries[k] for r in held for k in keys if k in r.entries).get("depth_unit") or ""
    xlabel = {"tau": "optical depth tau", "m": "depth z (m)"}.get(unit, f"depth ({unit})" if unit else "depth")
    ref = "Kirk's relation" if is_kirk(problem) else "M93 mean"
    the_ref = ref if is_kirk(problem) else "the " + ref
    reported = any(not r.entries[k].get("scored", True) for r in held for k in keys if k in r.entries)
    has_dirsig = any(dirsig_value(k) is not None for k in keys)
    w, h, left, gap, row = 330, 190, 80, 100, 262
    width = left + 2 * w + gap + 30
    keys_svg, legend_bottom = legend(left, 44, width - left - 40, [(r.name, c) for r, c in zip(held, colours)], ref,
                                     has_dirsig, reported)
    top = legend_bottom + 40
    # At each depth, the stores' markers (and DIRSIG's after a gap), `step` pixels apart, centred.
    step, n = 9.0, len(held)
    last = n + 0.5 if has_dirsig else n - 1  # the stores at 0 .. n-1, DIRSIG at n + 0.5
    offsets = [(j - last / 2) * step for j in range(n)]
    dirsig_offset = last / 2 * step
    half_width = last / 2 * step + 10
    parts = []
    for i, quantity in enumerate(quantities):
        series = quantity_series(quantity, keys, held)
        axis = DepthAxis([s[0] for s in series])
        y0 = top + row * i
        vp = Panel(left, y0, w, h, axis, *value_range(series))
        vp.frame(f"{problem}: {quantity}", quantity + (f" ({UNITS[quantity]})" if quantity in UNITS else ""), xlabel)
        r = error_range(series)
        ep = Panel(left + w + gap, y0, w, h, axis, -r, r, False)
        ep.frame(f"{problem}: {quantity}, relative error", f"relative error to {the_ref} (%)", xlabel)
        with_ref = [s for s in series if not math.isnan(s[1]) and s[1]]
        for depth, reference, spread, _, _ in with_ref:
            spread = 0.0 if math.isnan(spread) else spread
            vp.spread_box(depth, reference * (1 - spread), reference * (1 + spread), half_width)
            ep.spread_box(depth, -100 * spread, 100 * spread, half_width)
        if with_ref:
            vp.reference_line([s[0] for s in with_ref], [s[1] for s in with_ref], half_width)
            ep.reference_line([s[0] for s in with_ref], [0.0] * len(with_ref), half_width)
        for depth, reference, _, dirsig, entries in series:
            has_ref = not math.isnan(reference) and reference != 0
            for j, e in enumerate(entries):
                v, se = (number(e.get("value")), number(e.get("se"))) if e is not None else (math.nan, 0.0)
                if math.isnan(v):
                    continue
                se = 0.0 if math.isnan(se) else se
                colour, scored = colours[j], e.get("scored", True)
                vp.point(depth, offsets[j], v, v - 2 * se, v + 2 * se, colour, scored)
                if has_ref:
                    k = 100 / abs(reference)
                    ep.point(depth, offsets[j], k * (v - reference), k * (v - 2 * se - reference),
                             k * (v + 2 * se - reference), colour, scored)
            if dirsig is not None:
                vp.diamond(depth, dirsig_offset, dirsig)
                if has_ref:
                    ep.diamond(depth, dirsig_offset, 100 * (dirsig - reference) / reference)
        parts += vp.parts + ep.parts
    height = top + row * (len(quantities) - 1) + h + 45
    svg = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif">',
           '<rect width="100%" height="100%" fill="white"/>', svg_text(width / 2, 22, problem_title(problem), 15)]
    return "\n".join(svg + keys_svg + parts + ["</svg>"]) + "\n"


def legend(x, y, room, stores, ref, dirsig, reported):
    """The keys in rows under the title, wrapped within `room` pixels (stores: (name, colour));
    returns the SVG elements and the baseline of the last row."""
    items = [("band", f"{ref} ± s/x"), ("line", ref)]
    items += [("store", store) for store in stores]
    if dirsig:
        items.append(("diamond", "DIRSIG (manual Tables 7.1, 7.2)"))
    if reported:
        items.append(("open", "open: reported, not scored"))
    parts, cx, cy = [], x, y
    for kind, what in items:
        label = what[0] + " ± 2 SE" if kind == "store" else what
        span = 52 + 6.2 * len(label)
        if cx + span > x + room and cx > x:
            cx, cy = x, cy + 18
        if kind == "band":
            parts.append(f'<rect x="{cx}" y="{cy - 9}" width="26" height="10" fill="#bbb" fill-opacity="0.55"/>')
        elif kind == "line":
            parts.append(svg_line(cx, cy - 4, cx + 26, cy - 4, "#555", 1.5, "5,3"))
        elif kind == "store":
            parts += [svg_line(cx + 13, cy - 10, cx + 13, cy + 2, what[1], 1.5),
                      svg_circle(cx + 13, cy - 4, what[1], what[1])]
        elif kind == "open":
            parts.append(svg_circle(cx + 13, cy - 4, "white", "#333"))
        else:
            parts.append(svg_diamond(cx + 13, cy - 4))
        parts.append(svg_text(cx + 32, cy, label, 11, "start"))
        cx += span
    return parts, cy


# ---- main ----------------------------------------------------------------------------------

def inputs(args):
    """The runs' files, the seed studies' files and the output directory."""
    paths, studies = [], list(args.seed_study)
    for p in args.inputs:
        if os.path.isdir(p):
            paths += order_runs(glob.glob(os.path.join(p, "conformance_*.json")))
            studies += sorted(glob.glob(os.path.join(p, "seed_study_*.json")))
        elif os.path.isfile(p):
            paths.append(p)
        else:
            sys.exit(f"conformance_report.py: {p}: no such file or directory")
    if not paths:
        sys.exit("conformance_report.py: no conformance_*.json given or found")
    first = args.inputs[0]
    out = args.out or (first if os.path.isdir(first) else os.path.dirname(os.path.abspath(first)))
    return paths, list(dict.fromkeys(studies)), out


def write(runs, studies, out):
    """Writes the markdown and the SVGs into `out`; returns the paths written."""
    os.makedirs(out, exist_ok=True)
    written = [os.path.join(out, "conformance_report.md")]
    with open(written[0], "w", encoding="utf-8") as f:
        f.write(report(runs, studies))
    for problem, keys in rows_by_problem(runs).items():
        path = os.path.join(out, svg_name(problem))
        with open(path, "w", encoding="utf-8") as f:
            f.write(figure(problem, keys, runs))
        written.append(path)
    return written


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                     usage="%(prog)s [--out DIR] [--seed-study FILE.json ...] (DIR | FILE.json ...)")
    parser.add_argument("inputs", nargs="+", help="a directory of conformance_*.json, or the files")
    parser.add_argument("--out", help="output directory (default: the input directory)")
    parser.add_argument("--seed-study", action="append", default=[], metavar="FILE.json",
                        help="a seed_study_<store>.json of scripts/seed_study.py to add (repeatable)")
    args = parser.parse_args(argv)
    paths, study_paths, out = inputs(args)
    runs = [Run(p) for p in paths]
    studies = [(p, seed_study.load_study(p)) for p in study_paths]
    written = write(runs, studies, out)
    for run in runs:
        passing, scored, _ = tally(run)
        print(f"{run.name}: {passing} of {scored} scored entries pass")
    print("conformance report: " + written[0])
    print("figures: " + " ".join(os.path.basename(p) for p in written[1:]))


if __name__ == "__main__":
    main(sys.argv[1:])
