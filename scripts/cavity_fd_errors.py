#!/usr/bin/env python3
"""RMS errors of recorded cavity profiles against the finite-difference reference.

Usage: scripts/cavity_fd_errors.py RESULTS.csv [REFERENCE.csv] [--column N512]

RESULTS.csv: a published results file (docs/results/<study>.csv, or `runner export`) of a
cavity study at Re = 100; its jobs record u_x and u_y at Ghia, Ghia & Shin's 17 points
(ux_at_y_<y>, uy_at_x_<x>) and ux_rms_err / uy_rms_err against Ghia's table. REFERENCE.csv:
the output of `build/cavity_fd 100 128 256 512` (default reference/cavity_re100_fd.csv).
For each job: the recorded errors against Ghia, and the same RMS (the 15 interior points of each
centreline) against the reference's column (default N512, the finest grid).
"""
import csv
import json
import math
import os
import sys
from collections import defaultdict


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    column = "N512"
    if "--column" in argv:
        column = argv[argv.index("--column") + 1]
        args.remove(column)
    if not args:
        sys.exit(__doc__)
    here = os.path.dirname(os.path.abspath(__file__))
    ref_path = args[1] if len(args) > 1 else os.path.join(here, "..", "reference",
                                                           "cavity_re100_fd.csv")
    ref = {}
    with open(ref_path) as f:
        for r in csv.DictReader(f):
            if column not in r:
                sys.exit(f"{ref_path}: no column {column}")
            name = ("ux_at_y_" if r["profile"] == "u_at_y" else "uy_at_x_") + r["coord"]
            ref[name] = float(r[column])
    jobs = defaultdict(dict)
    params = {}
    with open(args[0]) as f:
        for r in csv.DictReader(f):
            jobs[r["job"]][r["metric"]] = float(r["value"])
            params[r["job"]] = (r.get("tier", ""), json.loads(r["params"]))
    out = csv.writer(sys.stdout, lineterminator="\n")
    out.writerow(["tier", "dx", "params", "ux_rms_err", "uy_rms_err", "ux_rms_err_fd",
                  "uy_rms_err_fd"])
    for job, m in jobs.items():
        tier, p = params[job]
        if p.get("Re") != 100.0 or "ux_rms_err" not in m:
            continue
        err = {}
        for prefix in ("ux_at_y_", "uy_at_x_"):
            names = [n for n in ref if n.startswith(prefix)]
            inner = [n for n in names if 0.0 < float(n[len(prefix):]) < 1.0]
            if any(n not in m for n in inner):
                break
            err[prefix] = math.sqrt(sum((m[n] - ref[n]) ** 2 for n in inner) / len(inner))
        if len(err) < 2:
            continue
        rest = {k: v for k, v in p.items() if k not in ("Re", "dx")}
        out.writerow([tier, p.get("dx"), json.dumps(rest, sort_keys=True)] +
                     [f"{v:.4f}" for v in (m["ux_rms_err"], m["uy_rms_err"], err["ux_at_y_"],
                                           err["uy_at_x_"])])


if __name__ == "__main__":
    main(sys.argv[1:])
