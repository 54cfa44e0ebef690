#!/usr/bin/env python3
"""Every published run is still a job of its study: the runner's current expansion reproduces it.

A job's key is the hash of its canonical parameters, so it changes when a study's tier, a case's
or scheme's parameter table, or its defaults change. A published run (docs/results/<study>.csv,
written by `runner publish`) whose key no tier of its study expands to any more is orphaned:
`runner status` and `runner table` no longer find it, and re-running the study computes it again
under a new key. This check runs `runner run studies/<study>.toml [--tier T] [--set K=V ...]
--dry-run` for every tier a published row names (`tier` column: tiers joined by ';', a tier's
`--set` overrides after '+', comma separated; `full` is the study without a tier) and requires
every published key among the listed jobs of at least one of them.

Not checked: studies with a `[search]` section (their probes depend on the results of earlier
probes, which a dry run on an empty database does not have). Known exceptions are listed in
EXCEPTIONS with their reason; an exception that no longer applies fails too, so the list stays
true.

Usage: published_keys.py RUNNER SOURCE_DIR
"""
import collections
import csv
import glob
import os
import re
import subprocess
import sys
import tempfile

# (study, tier as published, key prefix): why its key is no longer in the expansion.
EXCEPTIONS = {
    ("isph_cavity", "fine", "a9379cf66e60"):
        "the tier's first run at the paper's dt = 0.001 (diverged at t = 0.498, docs/isph.md); the "
        "tier now runs dt = 0.0005",
}

KEY_LINE = re.compile(r"^\s*\S+\s+([0-9a-f]{12})\b", re.M)


def listed_keys(runner, study_file, tier, db):
    name, _, sets = tier.partition("+")
    cmd = [runner, "run", study_file, "--dry-run", "--db", db]
    if name != "full":
        cmd += ["--tier", name]
    for s in sets.split(",") if sets else []:
        cmd += ["--set", s]
    out = subprocess.run(cmd, capture_output=True, text=True)
    if out.returncode != 0:
        return None, out.stderr.strip().splitlines()[-1] if out.stderr.strip() else "failed"
    return set(KEY_LINE.findall(out.stdout)), None


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    runner, root = os.path.abspath(sys.argv[1]), sys.argv[2]
    os.chdir(root)
    failures, checked, used = [], 0, set()
    with tempfile.TemporaryDirectory() as tmp:
        db = os.path.join(tmp, "empty.sqlite")
        for path in sorted(glob.glob("docs/results/*.csv")):
            groups = collections.defaultdict(set)
            with open(path, newline="") as f:
                for row in csv.DictReader(f):
                    groups[(row["study"], row["tier"])].add(row["job"][:12])
            for (study, tiers), keys in sorted(groups.items()):
                study_file = f"studies/{study}.toml"
                if not os.path.exists(study_file):
                    failures.append(f"{path}: study file {study_file} of tier '{tiers}' is gone")
                    continue
                with open(study_file) as f:
                    if re.search(r"^\[search\]", f.read(), re.M):
                        continue
                listed, errors = set(), []
                for tier in tiers.split(";"):
                    got, err = listed_keys(runner, study_file, tier, db)
                    if got is None:
                        errors.append(f"tier '{tier}': {err}")
                    else:
                        listed |= got
                for key in sorted(keys - listed):
                    if (study, tiers, key) in EXCEPTIONS:
                        used.add((study, tiers, key))
                        continue
                    failures.append(
                        f"{path}: published job {key} (tier '{tiers}') is not a job of "
                        f"{study_file} any more" + (f" ({'; '.join(errors)})" if errors else ""))
                checked += len(keys)
    for e in sorted(set(EXCEPTIONS) - used):
        failures.append(f"exception {e} no longer applies: remove it from EXCEPTIONS")
    for f in failures:
        print("FAIL", f)
    print(f"{checked} published jobs checked, {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
