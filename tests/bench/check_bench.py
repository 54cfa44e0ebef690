#!/usr/bin/env python3
"""CI check of every script and program in bench/ at the tiny size its header documents (seconds
each): it runs as shipped and prints its numbers, and the numbers it derives (ratios, medians,
steady-state steps) agree with the rows it printed beside them; where the bench measures on a known
configuration, the count it reports is checked against that configuration. The A/B scripts compare
the runner with itself. LAMMPS (lammps_ab) and PySPH (pysph_tgv) must be installed
(scripts/install_deps.sh --tests installs them): without them the check fails, it is not skipped.

Usage: check_bench.py WHAT SRC RUNNER SPH_BENCH PPE_BENCH
  WHAT: sph_bench, ppe_bench, alsph_ab, one_ab, tvf_ab, lammps_ab or pysph_tgv
"""

import json
import math
import os
import re
import subprocess
import sys
import tempfile
import types

failures = []


def check(cond, what):
    print(("ok   " if cond else "FAIL ") + what)
    if not cond:
        failures.append(what)


def run(cmd, **env):
    """Runs cmd (one thread, extra environment env); its output is printed and returned. A non-zero
    exit ends the check."""
    e = dict(os.environ, OMP_NUM_THREADS="1", OMP_WAIT_POLICY="passive", **env)
    p = subprocess.run(cmd, env=e, capture_output=True, text=True)
    sys.stdout.write(p.stdout)
    sys.stdout.write(p.stderr)
    if p.returncode != 0:
        sys.exit("FAIL %s exited with %d" % (" ".join(cmd), p.returncode))
    return p.stdout


def close(printed, value, rel=0.01):
    """A printed number (3 significant digits) against its recomputation."""
    return math.isfinite(value) and abs(float(printed) - value) <= rel * abs(value)


def positive(x):
    return math.isfinite(x) and x > 0


def csv_rows(out, pattern):
    return [line.split(",") for line in out.splitlines() if re.match(pattern, line)]


NUM = r"(-?[0-9.]+(?:e[-+]?[0-9]+)?)"


def sph_bench(a):
    out = run([a.sph_bench, "--n", "1000", "--threads", "1", "--csv"])
    rows = csv_rows(out, r"^[23],")
    measures = {"cell list build", "neighbour list build", "verlet candidates", "verlet list build",
                "pair geometry (verlet list)", "density (cell list)", "density (neighbour list)",
                "pressure grad (cell list)", "pressure grad (nbr list)"}
    for dim, n in (("2", 1024), ("3", 1000)):
        mine = [r for r in rows if r[0] == dim]
        check(sorted(r[4] for r in mine) == sorted(measures), "%sD: the nine measures" % dim)
        check(all(int(r[1]) == n for r in mine), "%sD: %d particles (lattice of side N^(1/D))"
              % (dim, n))
        check(all(positive(float(r[5])) for r in mine), "%sD: every value positive" % dim)
        nbrs = float(mine[0][2]) if mine else float("nan")
        cand = [float(r[5]) for r in mine if r[4] == "verlet candidates"]
        check(bool(cand) and cand[0] > nbrs, "%sD: more Verlet candidates than neighbours" % dim)
        if dim == "2":
            # Lattice points within 2.6 dx of a point: 20. Under the +-0.1 dx disorder those at
            # sqrt(5) dx stay inside, the next (sqrt(8) dx = 2.83 dx) seldom come in: 20.0 to the
            # printed digit.
            check(nbrs == 20.0, "2D: 20.0 neighbours per particle (the lattice count), got %g"
                  % nbrs)
        else:
            # 80 lattice points within 2.6 dx; the 24 at sqrt(6) dx = 2.45 dx can leave, those at
            # sqrt(8) dx = 2.83 dx seldom come in.
            check(76.0 <= nbrs <= 80.5, "3D: 76-80.5 neighbours per particle (80 on the lattice), "
                  "got %g" % nbrs)


def ppe_bench(a):
    out = run([a.ppe_bench, "--dx", "0.05", "--warm", "2", "--steps", "2", "--rounds", "2",
               "--variants", "bicgstab_ilu0,bicgstab_amg", "--threads", "1"])
    # The cavity at dx = 1/20: 20 x 20 fluid particles and three wall layers on each side.
    per_round = [line.split() for line in out.splitlines() if re.match(r"^\d+ +bicgstab_", line)]
    check(len(per_round) == 4 and all(r[0] == "676" for r in per_round),
          "two rounds of both variants, N = 676 = (20 + 6)^2")
    med = {line.split()[1]: [float(x) for x in line.split()[2:]]
           for line in out.splitlines() if re.match(r"^# bicgstab_\w+ +[0-9]", line)}
    check(set(med) == {"bicgstab_ilu0", "bicgstab_amg"}, "median lines of both variants")
    if set(med) != {"bicgstab_ilu0", "bicgstab_amg"}:
        return
    ilu, amg = med["bicgstab_ilu0"], med["bicgstab_amg"]
    # Medians over two rounds: the means of the rounds' it/solve, solve and step (wall and CPU).
    for name, m in med.items():
        rounds = [[float(x) for x in r[3:]] for r in per_round if r[1] == name]
        for col, rcol, what in ((0, 0, "it/solve"), (2, 3, "solve"), (3, 4, "step"),
                                (5, 6, "solve_cpu"), (6, 7, "step_cpu")):
            mean = sum(r[rcol] for r in rounds) / len(rounds)
            check(abs(m[col] - mean) <= 0.006 + 0.01 * mean,
                  "%s %s: median %g of the rounds' %s" % (name, what, m[col],
                                                         [r[rcol] for r in rounds]))
    # columns: it/solve setup solve step setup_cpu solve_cpu step_cpu solve_r step_r solvc_r stepc_r
    check(ilu[7:] == [1.0, 1.0, 1.0, 1.0], "ratios of the first variant to itself are 1")
    for col, r, name in ((2, 7, "solve_r"), (3, 8, "step_r"), (5, 9, "solvc_r"),
                         (6, 10, "stepc_r")):
        check(positive(amg[col]) and close(amg[r], ilu[col] / amg[col], 0.03),
              "bicgstab_amg %s %g = %g / %g" % (name, amg[r], ilu[col], amg[col]))
    check(0 < amg[0] < ilu[0], "BoomerAMG needs fewer iterations per solve (%g) than ILU(0) (%g)"
          % (amg[0], ilu[0]))


def alsph_ab(a):
    out = run([os.path.join(a.src, "bench", "alsph_ab.sh"), a.runner, a.runner, "2", "1"],
              D_OVER_DX="5", LONG_STEPS="4")
    cpu, it = {}, {}
    for r in csv_rows(out, r"^[AB],[12],1,"):
        key = (r[0], int(r[1]), int(float(r[6])))
        check(positive(float(r[3])) and positive(float(r[4])) and float(r[5]) >= 1,
              "row %s: positive costs, at least one inner iteration" % ",".join(r))
        cpu[key], it[key] = float(r[3]), float(r[4])
    # t_end follows D_OVER_DX: each job ran exactly the steps asked for.
    want = {(w, alg, n) for w in "AB" for alg in (1, 2) for n in (2, 4)}
    check(set(cpu) == want and len(csv_rows(out, r"^[AB],[12],1,")) == 8,
          "one run of 2 and one of 4 steps per binary and algorithm, got %s" % sorted(cpu))
    if set(cpu) != want:
        return
    for alg in (1, 2):
        m = re.search(r"^algorithm %d, 2 steps: step %sx, inner iteration %sx" % (alg, NUM, NUM),
                      out, re.M)
        check(bool(m) and close(m.group(1), cpu["A", alg, 2] / cpu["B", alg, 2])
              and close(m.group(2), it["A", alg, 2] / it["B", alg, 2]),
              "algorithm %d: the step and inner-iteration ratios A / B of its rows" % alg)
        m = re.search(r"^algorithm %d, steady state \(steps 3..4\): A %s, B %s CPU us per "
                      r"particle-step: %sx" % (alg, NUM, NUM, NUM), out, re.M)
        sa = (4 * cpu["A", alg, 4] - 2 * cpu["A", alg, 2]) / 2
        sb = (4 * cpu["B", alg, 4] - 2 * cpu["B", alg, 2]) / 2
        check(bool(m) and close(m.group(1), sa) and close(m.group(2), sb)
              and close(m.group(3), sa / sb),
              "algorithm %d: the steady-state step (4 x CPU(4) - 2 x CPU(2)) / 2 and its ratio"
              % alg)


def median(x):
    x = sorted(x)
    return x[len(x) // 2] if len(x) % 2 else 0.5 * (x[len(x) // 2 - 1] + x[len(x) // 2])


def one_ab_check(out, repeats):
    """bench/one_ab.sh's rows (binary, run, CPU per particle-step, steps, neighbour builds) and
    its medians."""
    rows = csv_rows(out, r"^[AB],\d+,")
    check(sorted((r[0], r[1]) for r in rows) == sorted((w, str(k)) for w in "AB"
                                                      for k in range(1, repeats + 1)),
          "%d runs of each binary" % repeats)
    check(all(positive(float(r[2])) for r in rows), "positive CPU per particle-step")
    check(len({tuple(r[3:]) for r in rows}) == 1 and int(rows[0][3]) > 0,
          "the same binary ran the same steps and neighbour builds every time (%s)"
          % sorted({", ".join(r[3:]) for r in rows}))
    a_ = median(float(r[2]) for r in rows if r[0] == "A")
    b_ = median(float(r[2]) for r in rows if r[0] == "B")
    m = re.search(r"^CPU per particle-step: A %s us, B %s us \(medians\), A / B = %s$"
                  % (NUM, NUM, NUM), out, re.M)
    check(bool(m) and close(m.group(1), a_, 1e-3) and close(m.group(2), b_, 1e-3)
          and close(m.group(3), a_ / b_), "the medians of its rows and their ratio A / B")


def one_ab(a):
    one_ab_check(run([os.path.join(a.src, "bench", "one_ab.sh"), a.runner, a.runner, "1",
                      "cylinder_free_stream", "D_over_dx=5", "t_end=0.1", "boundary=free_stream",
                      "domain_length=8", "domain_height=4", "upstream_length=3"]), 1)


def tvf_ab(a):
    one_ab_check(run([os.path.join(a.src, "bench", "tvf_ab.sh"), a.runner, a.runner, "3", "20",
                      "0.05"]), 3)


def lammps_ab(a):
    out = run([os.path.join(a.src, "bench", "lammps_ab.sh"), "400", "1"], STEPS="50",
              BENCH=a.sph_bench)
    rows = {r[1]: r for r in csv_rows(out, r"^1,(LAMMPS|ours|ratio),")}
    check(set(rows) == {"LAMMPS", "ours", "ratio"}, "rows of LAMMPS, ours and their ratio")
    if set(rows) != {"LAMMPS", "ours", "ratio"}:
        return
    lmp, ours, ratio = rows["LAMMPS"], rows["ours"], rows["ratio"]
    check(all(positive(float(r[k])) for r in (lmp, ours) for k in (2, 3, 4)),
          "positive build and pair costs and list lengths")
    builds = re.search(r"builds=(\d+)", lmp[5])
    check(bool(builds) and int(builds.group(1)) >= 1, "LAMMPS rebuilt its list")
    check("within_support=20 " in ours[5], "ours: 20 neighbours within the support (the lattice)")
    b, p = float(ours[2]) / float(lmp[2]), float(ours[3]) / float(lmp[3])
    check(close(ratio[2], b) and close(ratio[3], p), "the ratios ours / LAMMPS of the two rows")
    m = re.search(r"^median ratios ours / LAMMPS over 1 alternated pairs: neighbour build %s, "
                  r"pair loop per particle-step %s$" % (NUM, NUM), out, re.M)
    check(bool(m) and close(m.group(1), b) and close(m.group(2), p), "the median ratios")


def pysph_tgv(a):
    with tempfile.TemporaryDirectory() as tmp:
        js = os.path.join(tmp, "tgv.json")
        # Debian's interpreter: python3-pysph installs PySPH for it.
        out = run(["/usr/bin/python3", os.path.join(a.src, "bench", "pysph_tgv.py"), "--nx", "20",
                   "--tf", "0.05", "--runner", a.runner, "--json", js])
        with open(js) as f:
            rows = {r["code"]: r for r in json.load(f)["rows"]}
    codes = sorted(rows)
    check(len(codes) == 3 and sum(c.startswith("PySPH") for c in codes) == 1
          and "ours wcsph_tvf, tvf = limited" in rows and "ours wcsph_tvf, tvf = original" in rows,
          "rows of PySPH and of our two variants: %s" % codes)
    for c, r in rows.items():
        check(r["n"] == 400, "%s: 20 x 20 particles" % c)
        check(all(math.isfinite(r[k]) and r[k] >= 0 for k in
                  ("ke_rate_rel_err", "ke_rel_err_end", "umax_rel_err_end", "l1_vel_err_end"))
              and positive(r["wall_s"]) and positive(r["us_per_particle_step"]),
              "%s: finite errors and a positive cost" % c)
        check(r["steps"] > 0, "%s: steps counted" % c)
        check(("| %s |" % c) in out, "%s: a row of the printed table" % c)
    for c, r in rows.items():
        if c.startswith("PySPH"):
            # dt = 0.25 dx / (c0 + U) with c0 = 10 U, dx = 1/20: round(0.05 / dt) = 44 steps.
            check(r["steps"] == 44, "PySPH ran 44 steps to t = 0.05 (its step count read: %s)"
                  % r["steps"])
            check(close(r["us_per_particle_step"], 1e6 * r["wall_s"] / (r["n"] * r["steps"]), 1e-9),
                  "PySPH: us per particle-step = its run time / (particles x steps)")


def main():
    what = sys.argv[1] if len(sys.argv) == 6 else ""
    checks = dict(sph_bench=sph_bench, ppe_bench=ppe_bench, alsph_ab=alsph_ab, one_ab=one_ab,
                  tvf_ab=tvf_ab, lammps_ab=lammps_ab, pysph_tgv=pysph_tgv)
    if what not in checks:
        sys.exit(__doc__)

    src, runner, sph_bench_exe, ppe_bench_exe = sys.argv[2:6]
    a = types.SimpleNamespace(src=src, runner=runner, sph_bench=sph_bench_exe,
                              ppe_bench=ppe_bench_exe)
    checks[what](a)
    if failures:
        sys.exit("%s: %d check(s) failed" % (what, len(failures)))
    print("%s: OK" % what)


if __name__ == "__main__":
    main()
