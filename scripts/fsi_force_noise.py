#!/usr/bin/env python3
"""Where the fluctuation of the force on the rigid cylinder-and-beam body comes from (fsi_beam
with rigid_beam = true: Turek & Hron's CFD2, steady in the benchmark).

Usage: scripts/fsi_force_noise.py JOB_DIR [--t0 T]

JOB_DIR: the output folder of one fsi_beam job run with particle snapshots close enough in time
to resolve the lift's fluctuation (tier cfd2_noise of studies/fsi_beam.toml: output_interval =
0.01, i.e. 10 samples per D / U). Uses the snapshots with t >= T (default: settle_fraction x
t_end from the job's params.json) and the job's HDF5 series (the per-step C_L, C_D).

Prints, from the fluid's force on each wall particle of the body (the snapshots' `wall_force`,
the reaction of the very pair terms the fluid felt, in units of 1/2 rho U^2 D):
  - C_L and C_D: mean and standard deviation over the window (snapshots and per-step series);
  - the lift's parts on the cylinder and on the beam's upper and lower faces, and for each face
    the standard deviation of its sum against sqrt(sum of its particles' variances): equal for
    fluctuations independent from particle to particle (particle noise), larger by up to
    sqrt(n) when the whole face is pushed at once (a pressure field coherent along it);
  - the spectral peaks of C_L's and C_D's fluctuation in f D / U, and their share below 0.5;
  - the fluid's velocity and pressure at probe points (Shepard-weighted mean of the fluid within
    0.02 of the point, weight 1 - r^2 / 0.02^2): mean and standard deviation, and rho c0 |dv|,
    the pressure fluctuation a sound wave of the measured velocity fluctuation carries.
"""
import glob
import json
import os
import sys

import h5py
import numpy as np
from snapshots import read_vtp, snapshot_files


def peaks(t, s, n=5, sep=0.08):
    """The n largest periodogram peaks of s(t) (resampled uniformly), in f D / U (D / U = 0.1),
    at least sep apart, and the share of the fluctuation's power below f D / U = 0.5."""
    tu = np.linspace(t[0], t[-1], 4096)
    x = np.interp(tu, t, s)
    x = x - x.mean()
    S = np.abs(np.fft.rfft(x * np.hanning(len(x)))) ** 2
    f = np.fft.rfftfreq(len(x), tu[1] - tu[0]) * 0.1
    out = []
    for k in np.argsort(S)[::-1]:
        if f[k] > 0 and all(abs(f[k] - q) > sep for q in out):
            out.append(f[k])
        if len(out) == n:
            break
    return out, S[(f > 0) & (f < 0.5)].sum() / S[1:].sum()


def main(argv):
    if not argv or argv[0].startswith("-"):
        sys.exit(__doc__)
    job = argv[0]
    prm = json.load(open(os.path.join(job, "params.json")))["identity_params"]
    t0 = float(argv[argv.index("--t0") + 1]) if "--t0" in argv else prm["settle_fraction"] * prm["t_end"]
    c0 = prm["c0_factor"] * 1.0  # U = 1
    q = 0.5 * 1.0 * 1.0 * 0.1    # 1/2 rho U^2 D
    files = snapshot_files(job)
    names = {"Points", "id", "kind", "fsi_beam/body", "wall_force", "velocity", "pressure"}
    probes = [(0.1, 0.2), (0.2, 0.3), (0.45, 0.25), (0.7, 0.2), (1.0, 0.2), (1.5, 0.2), (2.2, 0.2)]
    ts, F, pv, pp = [], [], {p: [] for p in probes}, {p: [] for p in probes}
    ids = pos = None
    for f in files:
        s = read_vtp(f, names)
        if s["t"] < t0:
            continue
        b = s["fsi_beam/body"] == 1.0
        o = np.argsort(s["id"][b])
        if ids is None:
            ids, pos = s["id"][b][o], s["Points"][b][o][:, :2]
        if not np.array_equal(s["id"][b][o], ids):
            sys.exit("the body's wall particles changed between snapshots")
        F.append(s["wall_force"][b][o][:, :2] / q)
        fl = s["kind"] == 0
        x, v, p = s["Points"][fl, :2], s["velocity"][fl, :2], s["pressure"][fl]
        for c in probes:
            w = np.clip(1.0 - ((x - c) ** 2).sum(1) / 0.02 ** 2, 0.0, None)
            pv[c].append((w[:, None] * v).sum(0) / w.sum())
            pp[c].append((w * p).sum() / w.sum())
        ts.append(s["t"])
    if len(ts) < 16:
        sys.exit(f"{job}: {len(ts)} snapshots at t >= {t0}; run with output_interval = 0.01")
    t, F = np.array(ts), np.array(F)
    CL, CD = F[:, :, 1].sum(1), F[:, :, 0].sum(1)
    print(f"{len(t)} snapshots, t = {t[0]:.3f} .. {t[-1]:.3f}; {len(ids)} wall particles on the body; "
          f"Re = {prm['Re']}, c0 = {c0} U, H/dx = {prm['H_over_dx']}")
    print(f"C_L mean {CL.mean():.3f} std {CL.std():.3f};  C_D mean {CD.mean():.3f} std {CD.std():.3f}  (snapshots)")
    h = h5py.File(glob.glob(os.path.join(job, "*.h5"))[0], "r")
    st = h["series/t"][:]
    w = st >= t0
    for name in ("cl", "cd"):
        s = h["series/" + name][:][w]
        pk, low = peaks(st[w], s)
        print(f"series {name}: mean {s.mean():.3f} std {s.std():.3f}; spectral peaks f D/U "
              + ", ".join(f"{x:.2f}" for x in pk) + f"; share below 0.5: {low:.2f}")
    x, y = pos[:, 0], pos[:, 1]
    on_cyl = np.hypot(x - 0.2, y - 0.2) < 0.05 + 1e-4
    parts = {"cylinder": on_cyl, "beam, upper face": ~on_cyl & (y > 0.2), "beam, lower face": ~on_cyl & (y < 0.2)}
    print("lift part         particles  mean    std   sqrt(sum of particle variances)")
    sums = {}
    for name, m in parts.items():
        fy = F[:, m, 1]
        sums[name] = S = fy.sum(1)
        print(f"{name:17s} {m.sum():5d} {S.mean():8.3f} {S.std():7.3f} {np.sqrt((fy.std(0) ** 2).sum()):7.3f}")
    print(f"correlation of the beam's upper and lower faces' lift: "
          f"{np.corrcoef(sums['beam, upper face'], sums['beam, lower face'])[0, 1]:.2f}")
    print("probe (x, y)   u mean  v mean   |dv| std  p mean  p std   rho c0 |dv|")
    for c in probes:
        a, b = np.array(pv[c]), np.array(pp[c])
        dv = np.sqrt(a[:, 0].var() + a[:, 1].var())
        print(f"({c[0]:.2f}, {c[1]:.2f})  {a[:, 0].mean():7.3f} {a[:, 1].mean():7.3f} {dv:8.4f} "
              f"{b.mean():7.3f} {b.std():6.3f}  {c0 * dv:8.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
