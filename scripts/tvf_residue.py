#!/usr/bin/python3
"""Transport-velocity residue of Taylor-Green particle snapshots (docs/tvf.md, "Why the limited
variant's tv_ratio_max exceeds 1 from the lattice").

For each snapshot (.vtp of `runner one taylor_green ... output_interval=...`, unit periodic box,
Wendland C2 kernel as the study's default) it recomputes with the scheme's formulas
  g_i = -sum_j 2 V_j dW/dr(r_ij) e_ij                      (residue, seed 002 eq. 14, B = I)
  psi_i = min(kappa h^2 |g_i|^2, 1),  Delta r_i = alpha h^2 psi_i g_i    (eqs. 15-16)
and prints the largest shift / h, where it sits, the share of particles with psi = 1, their
median distance to the stagnation points {0.25, 0.75}^2 and to the vortex centres {0, 0.5}^2 of
u = -cos(2 pi x) sin(2 pi y), v = sin(2 pi x) cos(2 pi y), and the smallest neighbour distance.
The snapshot is written after the step's shift, so it shows the residue the next step acts on.

Usage: /usr/bin/python3 scripts/tvf_residue.py [--dx DX] [--kappa K] [--alpha A] FILE.vtp ...
Needs Debian's python3-scipy and python3-numpy.
"""
import argparse

import numpy as np
from scipy.spatial import cKDTree
from snapshots import read_vtp


def load(fn):
    s = read_vtp(fn, {"Points", "velocity", "volume", "smoothing_length"})
    return (s["Points"][:, :2], s["velocity"][:, :2], s["volume"], s["smoothing_length"][0],
            s["t"])


def dW_dr(r, h):  # Wendland C2, 2D: W = 7 / (4 pi h^2) (1 - q/2)^4 (1 + 2q), q = r / h
    q = r / h
    return -5.0 * q * (1.0 - q / 2.0) ** 3 * 7.0 / (4.0 * np.pi * h**3)


def median_distance(x, centres):
    d = x[:, None, :] - np.array(centres)[None, :, :]
    d -= np.round(d)
    return np.median(np.linalg.norm(d, axis=2).min(axis=1))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--dx", type=float, default=0.01)
    ap.add_argument("--kappa", type=float, default=100.0)
    ap.add_argument("--alpha", type=float, default=0.2)
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    for fn in a.files:
        x, v, V, h, t = load(fn)
        x = np.mod(x, 1.0)
        tree = cKDTree(x, boxsize=1.0)
        ij = tree.query_pairs(2.0 * h, output_type="ndarray")
        i, j = ij[:, 0], ij[:, 1]
        d = x[i] - x[j]
        d -= np.round(d)
        r = np.linalg.norm(d, axis=1)
        f = (2.0 * dW_dr(r, h) / r)[:, None] * d  # 2 dW/dr e_ij
        g = np.zeros_like(x)
        np.add.at(g, i, -V[j][:, None] * f)
        np.add.at(g, j, V[i][:, None] * f)
        g2 = (g**2).sum(axis=1)
        psi = np.minimum(a.kappa * h * h * g2, 1.0)
        shift = np.linalg.norm(a.alpha * h * h * psi[:, None] * g, axis=1)
        k = np.argmax(shift)
        nn = tree.query(x, k=2)[0][:, 1]
        vn = np.linalg.norm(v, axis=1)
        line = (f"t {t:.4f}: max |shift|/h {shift[k] / h:.3f} at ({x[k, 0]:.3f}, {x[k, 1]:.3f}), "
                f"|v| there {vn[k]:.3f} (max {vn.max():.3f}); max h|g| {np.sqrt(g2.max()) * h:.2f}; "
                f"psi = 1: {100 * np.mean(psi >= 1):.1f} %; min neighbour distance / dx "
                f"{nn.min() / a.dx:.2f}")
        sat = x[psi >= 1]
        if len(sat):
            stag = [(p, q) for p in (0.25, 0.75) for q in (0.25, 0.75)]
            centre = [(p, q) for p in (0.0, 0.5) for q in (0.0, 0.5)]
            line += (f"; psi = 1 particles: median distance to a stagnation point "
                     f"{median_distance(sat, stag):.3f}, to a vortex centre "
                     f"{median_distance(sat, centre):.3f}")
        print(line)


if __name__ == "__main__":
    main()
