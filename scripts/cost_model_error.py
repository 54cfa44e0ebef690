#!/usr/bin/env python3
"""The cost model's error over the published runs: for each study tier whose every job is in
docs/results/STUDY.csv, the runner's dry-run estimate on an empty database (the shipped rates)
against the sum of the published jobs' CPU time (cpu_time_s).

Usage: scripts/cost_model_error.py RUNNER [STUDY[:TIER] ...]   (default: a tier per scheme)
"""
import csv, json, os, re, subprocess, sys, tempfile, collections

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT = ["alsph_dt:small", "isph_cavity:coarse", "isph_cavity_re100", "tvf_cavity:re100",
           "tvf_tgv", "tvf_cylinder:quick", "godunov_cylinders", "godunov_ball", "godunov_eta_num",
           "fsi_beam:cfd2", "visc_patch"]
UNIT = {"seconds": 1, "minutes": 60, "hours": 3600}


def published(study):
    cpu = {}
    path = os.path.join(ROOT, "docs", "results", study + ".csv")
    if not os.path.exists(path):
        return cpu
    for r in csv.DictReader(open(path)):
        if r["metric"] == "cpu_time_s":
            cpu[r["job"]] = float(r["value"])
    return cpu


def main():
    runner = sys.argv[1]
    items = sys.argv[2:] or DEFAULT
    print("| study | tier | jobs | estimated CPU s | published CPU s | estimate / published |")
    print("|---|---|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for item in items:
            study, _, tier = item.partition(":")
            args = [runner, "run", os.path.join(ROOT, "studies", study + ".toml"), "--dry-run",
                    "--db", os.path.join(tmp, "empty.sqlite")]
            if tier:
                args += ["--tier", tier]
            out = subprocess.run(args, capture_output=True, text=True).stdout
            keys = re.findall(r"^new\s+([0-9a-f]{12})", out, re.M)
            m = re.search(r"^estimate: ([0-9.e+]+) CPU (seconds|minutes|hours) for (\d+) of the (\d+)",
                          out, re.M)
            cpu = published(study)
            hit = [next((v for k, v in cpu.items() if k.startswith(p)), None) for p in keys]
            if not keys or not m or None in hit or m.group(3) != m.group(4):
                print(f"| {study} | {tier or 'full'} | {len(keys)} | (not every job published or estimated) | | |")
                continue
            est = float(m.group(1)) * UNIT[m.group(2)]
            pub = sum(hit)
            print(f"| {study} | {tier or 'full'} | {len(keys)} | {est:.4g} | {pub:.4g} | {est / pub:.2f} |")


main()
