#!/usr/bin/python3
"""Taylor-Green vortex side by side: PySPH's TVF scheme against our wcsph_tvf.

What it runs (both single-threaded, one after the other, on the same machine):
  * PySPH (Debian package python3-pysph, pysph/examples/taylor_green.py, scheme "tvf": Adami, Hu &
    Adams 2013 transport-velocity formulation, quintic spline, h = dx, dt = 0.25 h / (c0 + U),
    p_b = rho0 c0^2) at --nx N for --tf T, with about 50 outputs for the energy history;
  * our taylor_green case with scheme wcsph_tvf (each --tvf variant given, Wendland C2,
    h = 1.3 dx, dual-criteria time stepping) at n_side = N, t_end = T, through the runner.
Both are compared with the analytic solution (Taylor & Green 1937): |v|max = exp(b t),
E_k = E_k(0) exp(2 b t), b = -8 pi^2 / Re, with the same metric definitions as
solver/cases/taylor_green.cpp:
  ke_rate_rel_err   least-squares slope of ln E_k over the samples with t >= fit_start, against 2b
  ke_rel_err_end    |E_k(T) / (E_k(0) exp(2 b T)) - 1|
  umax_rel_err_end  ||v|max(T) / exp(b T) - 1|
  l1_vel_err_end    mean ||v_i| - |v_e(r_i)|| / mean |v_e(r_i)| at T (PySPH's own "l1")
Cost: wall time of the time loop (PySPH: "Run took", which excludes code generation and
compilation; ours: the case's wall_s), per particle and step. A PySPH step is one time step of
its integrator (one evaluation of all equations and one neighbour update); ours is one acoustic
sub-step (two pair loops), with the per-advection-step work (density summation, viscous force,
transport correction, neighbour search) spread over the sub-steps; both per-particle-step
numbers and the time to solution are printed.

Usage (after building the runner; --runner defaults to build/runner of this repository):
  /usr/bin/python3 bench/pysph_tgv.py --nx 100 --tf 5
Tiny size (the test bench_pysph_tgv; PySPH compiles its generated code on the first run, about
10 s of CPU, cached in ~/.pysph afterwards): --nx 20 --tf 0.05.
Prints a Markdown table; --json FILE also writes the numbers. Needs python3-pysph
(apt-get install -y python3-pysph) and Debian's /usr/bin/python3 (it has PySPH's modules).
"""

import argparse
import glob
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def fit_rate(t, ke, t0):
    t = np.asarray(t)
    ke = np.asarray(ke)
    keep = t >= t0
    return np.polyfit(t[keep], np.log(ke[keep]), 1)[0]


def run_pysph(nx, tf, reynolds, perturb, workdir, outputs):
    from pysph.examples.taylor_green import TaylorGreen, exact_solution
    from pysph.solver.utils import iter_output

    U, L = 1.0, 1.0
    dx = L / nx
    dt = 0.25 * dx / (10.0 * U + U)  # PySPH's dt_cfl for hdx = 1 (the smallest of its limits)
    steps = int(round(tf / dt))
    pfreq = max(1, steps // outputs)
    out = os.path.join(workdir, "pysph_tg")
    app = TaylorGreen(fname="taylor_green")
    app.run(["--nx", str(nx), "--tf", str(tf), "--re", str(reynolds), "--scheme", "tvf",
             "--pfreq", str(pfreq), "-d", out, "-q"] +
            (["--perturb", str(perturb)] if perturb > 0 else []))
    log = open(os.path.join(out, "taylor_green.log")).read()
    run_s = float(re_find(r"Run took: ([0-9.eE+-]+) secs", log))
    b = -8.0 * np.pi ** 2 / reynolds
    files = sorted(glob.glob(os.path.join(out, "taylor_green_*.hdf5")),
                   key=lambda f: int(re.search(r"_(\d+)\.hdf5$", f).group(1)))
    t, ke, umax = [], [], []
    last = None
    n_steps = None
    for sd, arr in iter_output(files, "fluid"):
        n_steps = int(sd["count"])  # the integrator's steps so far (the last output: the run's)
        u, v, m = arr.get("u"), arr.get("v"), arr.get("m")
        t.append(sd["t"])
        ke.append(0.5 * np.sum(m * (u * u + v * v)))
        umax.append(np.sqrt(u * u + v * v).max())
        last = (sd["t"], arr.get("x").copy(), arr.get("y").copy(), u.copy(), v.copy())
        n = len(u)
    T, x, y, u, v = last
    ue, ve, _ = exact_solution(U, b, T, x, y)
    vm, vme = np.sqrt(u * u + v * v), np.sqrt(ue * ue + ve * ve)
    return dict(t=t, ke=ke, umax=umax, T=T, n=n, steps=n_steps, wall_s=run_s,
                l1=np.mean(np.abs(vm - vme)) / np.mean(vme), dt=dt)


def re_find(pattern, text):
    m = re.findall(pattern, text)
    if not m:
        raise RuntimeError("pattern %r not found" % pattern)
    return m[-1]


def run_ours(runner, nx, tf, reynolds, perturb, tvfs, workdir):
    study = os.path.join(workdir, "bench_tgv.toml")
    with open(study, "w") as f:
        f.write('[study]\nname = "bench_tgv"\ncase = "taylor_green"\nscheme = "wcsph_tvf"\n'
                '[params]\nn_side = %d\nt_end = %r\nRe = %r\nperturb = %r\n'
                'riemann_dissipation = "none"\n[sweep]\ntvf = [%s]\n'
                % (nx, float(tf), float(reynolds), float(perturb), ", ".join('"%s"' % t for t in tvfs)))
    db = os.path.join(workdir, "bench.sqlite")
    env = dict(os.environ, OMP_NUM_THREADS="1")
    subprocess.run([runner, "run", study, "--db", db, "-j", "1", "--threads-per-job", "1",
                    "--progress", "plain"], check=True, env=env, stdout=sys.stderr)
    out = subprocess.run([runner, "export", "bench_tgv", "--db", db, "--format", "json"],
                         check=True, capture_output=True, text=True).stdout
    data = json.loads(out)
    jobs = data["jobs"] if isinstance(data, dict) else data
    return {j["params"]["tvf"]: j for j in jobs}


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--nx", type=int, default=100)
    ap.add_argument("--tf", type=float, default=5.0)
    ap.add_argument("--re", type=float, default=100.0)
    ap.add_argument("--runner", default=os.path.join(ROOT, "build", "runner"),
                    help="our runner binary (default: build/runner of this repository)")
    ap.add_argument("--tvf", default="limited,original",
                    help="our variants, comma-separated (none, original, smoothing_length, limited)")
    ap.add_argument("--perturb", type=float, default=0.3,
                    help="random shift of the initial lattice, fraction of dx (both codes; PySPH "
                    "shifts by U[0, perturb) dx, we by U[-perturb/2, perturb/2) dx)")
    ap.add_argument("--outputs", type=int, default=50, help="PySPH outputs over the run")
    ap.add_argument("--skip-pysph", action="store_true")
    ap.add_argument("--json", help="also write the numbers to this file")
    ap.add_argument("--workdir", help="keep outputs here (default: a temporary directory)")
    a = ap.parse_args()
    if not (os.path.isfile(a.runner) and os.access(a.runner, os.X_OK)):
        sys.exit("pysph_tgv.py: no runner binary at %s (build it: scripts/build.sh runner; or "
                 "pass --runner)" % a.runner)
    if not a.skip_pysph:
        try:
            import pysph  # noqa: F401
        except ImportError:
            sys.exit("pysph_tgv.py: PySPH is not importable by %s (Debian package python3-pysph; "
                     "run with /usr/bin/python3)" % sys.executable)

    workdir = a.workdir or tempfile.mkdtemp(prefix="pysph_tgv_")
    os.makedirs(workdir, exist_ok=True)
    try:
        compare(a, workdir)
    finally:
        if not a.workdir:
            shutil.rmtree(workdir, ignore_errors=True)


def compare(a, workdir):
    b = -8.0 * np.pi ** 2 / a.re
    rows = []
    ours = run_ours(a.runner, a.nx, a.tf, a.re, a.perturb, a.tvf.split(","), workdir)
    for tvf, j in ours.items():
        m = j["metrics"]
        rows.append(dict(code="ours wcsph_tvf, tvf = " + tvf,
                         ke_rate_rel_err=m["ke_rate_rel_err"], ke_rel_err_end=m["ke_rel_err_end"],
                         umax_rel_err_end=m["umax_rel_err_end"], l1_vel_err_end=m["l1_vel_err_end"],
                         n=m["n_particles"], steps=m["acoustic_steps"], wall_s=m["wall_s"],
                         us_per_particle_step=1e6 * m["time_per_particle_step_s"]))
    if not a.skip_pysph:
        p = run_pysph(a.nx, a.tf, a.re, a.perturb, workdir, a.outputs)
        ke0 = p["ke"][0]
        rows.append(dict(code="PySPH %s tvf (Adami 2013)" % __import__("pysph").__version__,
                         ke_rate_rel_err=abs(fit_rate(p["t"], p["ke"], 0.0) - 2 * b) / abs(2 * b),
                         ke_rel_err_end=abs(p["ke"][-1] / (ke0 * np.exp(2 * b * p["T"])) - 1),
                         umax_rel_err_end=abs(p["umax"][-1] / np.exp(b * p["T"]) - 1),
                         l1_vel_err_end=p["l1"], n=p["n"], steps=p["steps"], wall_s=p["wall_s"],
                         us_per_particle_step=1e6 * p["wall_s"] / (p["n"] * p["steps"])))
    print("Taylor-Green Re = %g, %d x %d particles, perturb %g dx, t_end = %g, 1 thread, "
          "load average %.1f\n" % (a.re, a.nx, a.nx, a.perturb, a.tf, os.getloadavg()[0]))
    print("| code | ke_rate_rel_err | ke_rel_err_end | umax_rel_err_end | l1_vel_err_end | "
          "steps | wall s | us / particle-step |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print("| %s | %.4f | %.4f | %.4f | %.4f | %d | %.1f | %.3f |" % (
            r["code"], r["ke_rate_rel_err"], r["ke_rel_err_end"], r["umax_rel_err_end"],
            r["l1_vel_err_end"], r["steps"], r["wall_s"], r["us_per_particle_step"]))
    if a.json:
        with open(a.json, "w") as f:
            json.dump(dict(nx=a.nx, tf=a.tf, re=a.re, rows=rows), f, indent=1)


if __name__ == "__main__":
    main()
