#!/usr/bin/env python3
"""Log-log SVG plot of search_bench's scaling rows (python3, standard library only).

    plot_scaling.py scaling.csv scaling.svg

Left panel: build time per record, k-d tree and VOI octree, with an N log N reference
(a flat line per record would mean O(N); N log N rises by a constant per decade).
Right panel: query time against N, k-d tree within and VOI along, at fixed radius
(k grows with N: O(log N + k)) and at fixed k (radius shrinks with N: only log N is left).
"""
import csv
import math
import sys


def read(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return [{k: float(v) for k, v in r.items()} for r in rows]


class Panel:
    def __init__(self, x0, y0, w, h, xs, ys, title, ylabel):
        self.x0, self.y0, self.w, self.h = x0, y0, w, h
        self.lx = (math.floor(math.log10(min(xs))), math.ceil(math.log10(max(xs))))
        self.ly = (math.floor(math.log10(min(ys))), math.ceil(math.log10(max(ys))))
        if self.ly[0] == self.ly[1]:
            self.ly = (self.ly[0], self.ly[0] + 1)
        self.title, self.ylabel = title, ylabel
        self.parts = []

    def px(self, x):
        return self.x0 + self.w * (math.log10(x) - self.lx[0]) / (self.lx[1] - self.lx[0])

    def py(self, y):
        return self.y0 + self.h - self.h * (math.log10(y) - self.ly[0]) / (self.ly[1] - self.ly[0])

    def frame(self):
        p = self.parts
        p.append(f'<rect x="{self.x0}" y="{self.y0}" width="{self.w}" height="{self.h}" fill="none" stroke="#333"/>')
        for e in range(self.lx[0], self.lx[1] + 1):
            x = self.px(10 ** e)
            p.append(f'<line x1="{x:.1f}" y1="{self.y0}" x2="{x:.1f}" y2="{self.y0 + self.h}" stroke="#ddd"/>')
            p.append(f'<text x="{x:.1f}" y="{self.y0 + self.h + 16}" text-anchor="middle" font-size="11">1e{e}</text>')
        for e in range(self.ly[0], self.ly[1] + 1):
            y = self.py(10 ** e)
            p.append(f'<line x1="{self.x0}" y1="{y:.1f}" x2="{self.x0 + self.w}" y2="{y:.1f}" stroke="#ddd"/>')
            p.append(f'<text x="{self.x0 - 6}" y="{y + 4:.1f}" text-anchor="end" font-size="11">1e{e}</text>')
        p.append(f'<text x="{self.x0 + self.w / 2}" y="{self.y0 - 8}" text-anchor="middle" font-size="13">{self.title}</text>')
        p.append(f'<text x="{self.x0 + self.w / 2}" y="{self.y0 + self.h + 34}" text-anchor="middle" font-size="12">records N</text>')
        p.append(f'<text transform="translate({self.x0 - 46},{self.y0 + self.h / 2}) rotate(-90)" text-anchor="middle" font-size="12">{self.ylabel}</text>')

    def line(self, xs, ys, colour, label, index, dash=False):
        pts = " ".join(f"{self.px(x):.1f},{self.py(y):.1f}" for x, y in zip(xs, ys) if y > 0)
        style = ' stroke-dasharray="5,4"' if dash else ""
        self.parts.append(f'<polyline points="{pts}" fill="none" stroke="{colour}" stroke-width="2"{style}/>')
        if not dash:
            for x, y in zip(xs, ys):
                if y > 0:
                    self.parts.append(f'<circle cx="{self.px(x):.1f}" cy="{self.py(y):.1f}" r="3" fill="{colour}"/>')
        ly = self.y0 + 14 + 16 * index
        self.parts.append(f'<line x1="{self.x0 + 10}" y1="{ly - 4}" x2="{self.x0 + 34}" y2="{ly - 4}" stroke="{colour}" stroke-width="2"{style}/>')
        self.parts.append(f'<text x="{self.x0 + 40}" y="{ly}" font-size="11">{label}</text>')


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_scaling.py scaling.csv scaling.svg")
    rows = read(sys.argv[1])
    n = [r["n"] for r in rows]
    kd_build = [r["kd_build_s"] * 1e9 / r["n"] for r in rows]
    voi_build = [r["voi_build_s"] * 1e9 / r["n"] for r in rows]
    # N log N reference per record, scaled to the k-d tree's last point: c log2 N.
    c = kd_build[-1] / math.log2(n[-1])
    ref_build = [c * math.log2(x) for x in n]
    left = Panel(80, 40, 380, 300, n, kd_build + voi_build + ref_build, "build time per record", "ns per record")
    left.frame()
    left.line(n, kd_build, "#1f77b4", "k-d tree (left-balanced)", 0)
    left.line(n, voi_build, "#d62728", "VOI octree", 1)
    left.line(n, ref_build, "#777", "c log2 N (N log N build)", 2, dash=True)

    q = {k: [r[k] for r in rows] for k in ("within_fixed_r_us", "within_fixed_k_us", "along_fixed_r_us", "along_fixed_k_us")}
    # O(log N) reference through the fixed-k within points' first value.
    c2 = q["within_fixed_k_us"][0] / math.log2(n[0])
    ref_q = [c2 * math.log2(x) for x in n]
    allq = [v for vs in q.values() for v in vs] + ref_q
    right = Panel(580, 40, 380, 300, n, allq, "query time", "microseconds per query")
    right.frame()
    right.line(n, q["within_fixed_r_us"], "#1f77b4", "k-d within, r = 0.05 (k grows with N)", 0)
    right.line(n, q["within_fixed_k_us"], "#17becf", "k-d within, k fixed (r ~ N^-1/3)", 1)
    right.line(n, q["along_fixed_r_us"], "#d62728", "VOI along, r = 0.05 (k grows with N)", 2)
    right.line(n, q["along_fixed_k_us"], "#ff7f0e", "VOI along, k fixed (r ~ N^-1/2)", 3)
    right.line(n, ref_q, "#777", "c log2 N", 4, dash=True)

    svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="1000" height="400" font-family="sans-serif">',
           '<rect width="100%" height="100%" fill="white"/>'] + left.parts + right.parts + ["</svg>"]
    with open(sys.argv[2], "w") as f:
        f.write("\n".join(svg) + "\n")


if __name__ == "__main__":
    main()
