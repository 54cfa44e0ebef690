#!/usr/bin/env python3
"""Centreline profiles of lid-driven cavity runs against Ghia et al. (1982), as an SVG.

usage: plot_profiles.py out.svg label1 ux1.csv uy1.csv [label2 ux2.csv uy2.csv ...]
  uxK.csv: "y,ux" rows (the HDF5 group profile_x0.5 of a run), uyK.csv: "x,uy" rows
  (profile_y0.5). Ghia's points are read from solver/data/ghia1982.hpp. Standard library only.
"""
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def ghia():
    text = (ROOT / "solver/data/ghia1982.hpp").read_text()
    arr = {}
    for name in ("y", "u", "x", "v"):
        m = re.search(r"ghia_re1000_%s\{(.*?)\};" % name, text, re.S)
        arr[name] = [float(t) for t in m.group(1).replace("\n", " ").split(",") if t.strip()]
    return arr


def read_csv(path):
    rows = [l.split(",") for l in Path(path).read_text().split() if l.strip()]
    return [float(r[0]) for r in rows], [float(r[1]) for r in rows]


COLORS = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]


def panel(x0, y0, w, h, xr, yr, series, points, xlabel, ylabel, title):
    sx = lambda v: x0 + (v - xr[0]) / (xr[1] - xr[0]) * w
    sy = lambda v: y0 + h - (v - yr[0]) / (yr[1] - yr[0]) * h
    out = [f'<rect x="{x0}" y="{y0}" width="{w}" height="{h}" fill="none" stroke="black"/>',
           f'<text x="{x0 + w / 2}" y="{y0 - 8}" text-anchor="middle" font-size="14">{title}</text>',
           f'<text x="{x0 + w / 2}" y="{y0 + h + 36}" text-anchor="middle" font-size="13">{xlabel}</text>',
           f'<text x="{x0 - 42}" y="{y0 + h / 2}" text-anchor="middle" font-size="13" '
           f'transform="rotate(-90 {x0 - 42} {y0 + h / 2})">{ylabel}</text>']
    for k in range(5):
        vx = xr[0] + k * (xr[1] - xr[0]) / 4
        vy = yr[0] + k * (yr[1] - yr[0]) / 4
        out.append(f'<text x="{sx(vx)}" y="{y0 + h + 16}" text-anchor="middle" font-size="11">{vx:.2g}</text>')
        out.append(f'<text x="{x0 - 6}" y="{sy(vy) + 4}" text-anchor="end" font-size="11">{vy:.2g}</text>')
    for i, (label, xs, ys) in enumerate(series):
        pts = " ".join(f"{sx(a):.1f},{sy(b):.1f}" for a, b in zip(xs, ys))
        out.append(f'<polyline points="{pts}" fill="none" stroke="{COLORS[i % 6]}" stroke-width="1.5"/>')
    for a, b in points:
        out.append(f'<circle cx="{sx(a):.1f}" cy="{sy(b):.1f}" r="3.5" fill="none" stroke="black"/>')
    return out


def main():
    out_path, args = sys.argv[1], sys.argv[2:]
    g = ghia()
    ux_series, uy_series, labels = [], [], []
    for k in range(0, len(args), 3):
        label, ux_csv, uy_csv = args[k:k + 3]
        y, ux = read_csv(ux_csv)
        x, uy = read_csv(uy_csv)
        ux_series.append((label, ux, y))  # plotted as ux (horizontal) against y
        uy_series.append((label, x, uy))
        labels.append(label)
    svg = ['<svg xmlns="http://www.w3.org/2000/svg" width="900" height="460" font-family="sans-serif">',
           '<rect width="900" height="460" fill="white"/>']
    svg += panel(70, 40, 330, 330, (-0.6, 1.0), (0.0, 1.0), ux_series,
                 list(zip(g["u"], g["y"])), "u_x(0.5, y)", "y", "u_x along x = 0.5")
    svg += panel(500, 40, 330, 330, (0.0, 1.0), (-0.6, 0.45), uy_series,
                 list(zip(g["x"], g["v"])), "x", "u_y(x, 0.5)", "u_y along y = 0.5")
    for i, label in enumerate(labels):
        svg.append(f'<line x1="80" y1="{420 + 0 * i}" x2="80" y2="{420}" stroke="none"/>')
        xx = 70 + 200 * i
        svg.append(f'<line x1="{xx}" y1="430" x2="{xx + 25}" y2="430" stroke="{COLORS[i % 6]}" stroke-width="2"/>')
        svg.append(f'<text x="{xx + 30}" y="434" font-size="12">{label}</text>')
    xx = 70 + 200 * len(labels)
    svg.append(f'<circle cx="{xx + 12}" cy="430" r="3.5" fill="none" stroke="black"/>')
    svg.append(f'<text x="{xx + 30}" y="434" font-size="12">Ghia et al. 1982, Re = 1000</text>')
    svg.append("</svg>")
    Path(out_path).write_text("\n".join(svg))


if __name__ == "__main__":
    main()
