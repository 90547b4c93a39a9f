#!/usr/bin/env python3
"""Draws the spectral example's CSV (build/examples/spectral_case1 --csv FILE: rows
wavelength_nm, depth_m, quantity, value, se) as an SVG of two panels: the remote-sensing
reflectance Rrs(lambda) with +-1 SE bars, and Ed(lambda) at each depth. Python's standard
library only; the drawing helpers are the conformance report's.

    python3 scripts/plot_spectral.py spectral_case1.csv docs/images/spectral_case1.svg
"""
import csv
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from conformance_report import linear_ticks, svg_line, svg_text  # noqa: E402

COLOURS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def read(path):
    rows = {}
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            key = (r["quantity"], float(r["depth_m"]))
            rows.setdefault(key, []).append((float(r["wavelength_nm"]), float(r["value"]), float(r["se"])))
    return rows


def panel(x0, width, height, title, ylabel, series, lines):
    """One panel at x0: series = [(label, colour, [(wl, value, se)])], error bars where se > 0."""
    top, left, plot_w, plot_h = 30, x0 + 70, width - 90, height - 80
    wls = [p[0] for _, _, pts in series for p in pts]
    ys = [p[1] + p[2] for _, _, pts in series for p in pts]
    x_lo, x_hi = min(wls), max(wls)
    y_hi = max(ys) * 1.05
    sx = lambda w: left + (w - x_lo) / (x_hi - x_lo) * plot_w  # noqa: E731
    sy = lambda v: top + plot_h - v / y_hi * plot_h  # noqa: E731
    lines.append(svg_text(left + plot_w / 2, top - 10, title, 14))
    lines.append(svg_line(left, top + plot_h, left + plot_w, top + plot_h, "black"))
    lines.append(svg_line(left, top, left, top + plot_h, "black"))
    for t in linear_ticks(x_lo, x_hi, 6):
        lines.append(svg_line(sx(t), top + plot_h, sx(t), top + plot_h + 5, "black"))
        lines.append(svg_text(sx(t), top + plot_h + 18, f"{t:g}", 11))
    for t in linear_ticks(0.0, y_hi, 5):
        lines.append(svg_line(left - 5, sy(t), left, sy(t), "black"))
        lines.append(svg_text(left - 8, sy(t) + 4, f"{t:.3g}", 11, anchor="end"))
    lines.append(svg_text(left + plot_w / 2, top + plot_h + 40, "wavelength (nm)", 12))
    lines.append(svg_text(x0 + 16, top + plot_h / 2, ylabel, 12, rotate=True))
    for k, (label, colour, pts) in enumerate(series):
        pts = sorted(pts)
        path = " ".join(f"{'M' if i == 0 else 'L'}{sx(w):.1f},{sy(v):.1f}" for i, (w, v, _) in enumerate(pts))
        lines.append(f'<path d="{path}" fill="none" stroke="{colour}" stroke-width="1.5"/>')
        for w, v, se in pts:
            if se > 0:
                lines.append(svg_line(sx(w), sy(v - se), sx(w), sy(v + se), colour))
        lines.append(svg_line(left + plot_w - 120, top + 12 + 16 * k, left + plot_w - 100, top + 12 + 16 * k, colour, 2))
        lines.append(svg_text(left + plot_w - 95, top + 16 + 16 * k, label, 11, anchor="start"))


def main(argv):
    if len(argv) != 3:
        sys.exit(__doc__)
    rows = read(argv[1])
    rrs = [(k, v) for k, v in rows.items() if k[0] == "Rrs"]
    ed = sorted((k, v) for k, v in rows.items() if k[0] == "Ed")
    if not rrs or not ed:
        sys.exit(f"{argv[1]}: no Rrs or Ed rows")
    width, height = 920, 360
    lines = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" font-family="sans-serif">',
             f'<rect width="{width}" height="{height}" fill="white"/>']
    panel(0, width / 2, height, "Remote-sensing reflectance", "Rrs (1/sr)", [("Rrs", COLOURS[0], rrs[0][1])], lines)
    panel(width / 2, width / 2, height, "Downward irradiance (per unit E_perp)", "Ed",
          [(f"{depth:g} m", COLOURS[i % len(COLOURS)], pts) for i, ((_, depth), pts) in enumerate(ed)], lines)
    lines.append("</svg>")
    with open(argv[2], "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv)
