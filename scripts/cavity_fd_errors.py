#!/usr/bin/env python3
"""RMS errors of recorded cavity profiles against the finite-difference reference.

Usage: scripts/cavity_fd_errors.py RESULTS.csv [--re RE] [--column N512]

RESULTS.csv: a published results file (docs/results/<study>.csv) of a cavity study; its jobs
record u_x and u_y at Ghia, Ghia & Shin's 17 points (ux_at_y_<y>, uy_at_x_<x>) and ux_rms_err /
uy_rms_err against Ghia's table. The reference: reference/cavity_re<RE>_fd.csv (RE = 100 by
default, or 1000), the output of `build/cavity_fd RE 128 256 512`. For each job at that Re: the
recorded errors against Ghia, and the same RMS (the 15 interior points of each centreline)
against the reference's column (N512, the finest grid, by default; `richardson` the
extrapolation of 256 and 512).
"""
import csv
import json
import math
import os
import sys
from collections import defaultdict


def main(argv):
    args = [a for a in argv if not a.startswith("--")]
    opts = {"--column": "N512", "--re": "100"}
    for o in opts:
        if o in argv:
            opts[o] = argv[argv.index(o) + 1]
            args.remove(opts[o])
    column, Re = opts["--column"], float(opts["--re"])
    if not args:
        sys.exit(__doc__)
    here = os.path.dirname(os.path.abspath(__file__))
    ref_path = os.path.join(here, "..", "reference", f"cavity_re{Re:g}_fd.csv")
    ref = {}
    with open(ref_path) as f:
        for r in csv.DictReader(f):
            if column not in r:
                sys.exit(f"{ref_path}: no column {column}")
            name = ("ux_at_y_" if r["profile"] == "u_at_y" else "uy_at_x_") + r["coord"]
            ref[name] = float(r[column])
    # The 15 interior points of each centreline (the walls' values are exact).
    inner = {prefix: [n for n in ref if n.startswith(prefix) and 0.0 < float(n[len(prefix):]) < 1.0]
             for prefix in ("ux_at_y_", "uy_at_x_")}
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
        if p.get("Re") != Re or "ux_rms_err" not in m:
            continue
        if any(n not in m for names in inner.values() for n in names):
            continue
        err = {prefix: math.sqrt(sum((m[n] - ref[n]) ** 2 for n in names) / len(names))
               for prefix, names in inner.items()}
        rest = {k: v for k, v in p.items() if k not in ("Re", "dx")}
        out.writerow([tier, p.get("dx"), json.dumps(rest, sort_keys=True)] +
                     [f"{v:.4f}" for v in (m["ux_rms_err"], m["uy_rms_err"], err["ux_at_y_"],
                                           err["uy_at_x_"])])


if __name__ == "__main__":
    main(sys.argv[1:])
