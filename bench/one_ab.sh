#!/usr/bin/env bash
# A B A B comparison of two runner binaries on one job of a case (`runner one CASE k=v ...`), one
# thread, each run in a fresh database, alternated so that both see the same load. Prints, per
# run, the process CPU time per particle and step of the time loop (cpu_time_per_step_s /
# n_particles, the job's own metrics: for wcsph_tvf an advection step; n_particles is the largest
# count of the run), the steps and the Verlet list builds where the binary reports them, then the
# median ratio A / B (above 1: B is cheaper).
#   bench/one_ab.sh OLD_RUNNER NEW_RUNNER REPEATS CASE [--scheme S] [KEY=VALUE ...]
# e.g. bench/one_ab.sh old/runner build/runner 3 cylinder_free_stream D_over_dx=20 t_end=10 \
#        boundary=free_stream domain_length=17 domain_height=8 upstream_length=7 refinement_band=2
# The size is the case's own parameters; a tiny one (a second; the test bench_one_ab):
#   bench/one_ab.sh build/runner build/runner 1 cylinder_free_stream D_over_dx=5 t_end=0.1 \
#     boundary=free_stream domain_length=8 domain_height=4 upstream_length=3
set -euo pipefail
A="$1" B="$2" REPEATS="$3"
shift 3
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
export OMP_NUM_THREADS=1
echo "binary,run,cpu_us_per_particle_step,steps,neighbour_builds"
for r in $(seq "$REPEATS"); do
  for who in A B; do
    bin="$A"; [ "$who" = B ] && bin="$B"
    "$bin" one "$@" --db "$TMP/$who$r.sqlite" --threads-per-job 1 >"$TMP/$who$r.log" 2>&1 ||
      { cat "$TMP/$who$r.log" >&2; echo "one_ab.sh: $bin failed (log above)" >&2; exit 1; }
    awk -v who="$who" -v r="$r" '
      $1 == "cpu_time_per_step_s" { c = $2 } $1 == "n_particles" { n = $2 }
      $1 == "steps" { s = $2 } $1 == "neighbour_builds" { b = $2 }
      END { if (c == "" || n == "") {
              print "one_ab.sh: no cpu_time_per_step_s or n_particles among the metrics" > "/dev/stderr"
              exit 1 }
            printf "%s,%s,%.4g,%s,%s\n", who, r, 1e6 * c / n, s, b }' "$TMP/$who$r.log" ||
      { cat "$TMP/$who$r.log" >&2; exit 1; }
  done
done | tee "$TMP/all.csv"
awk -F, '{ v[$1] = v[$1] " " $3 }
  function med(s,   a, n, i, j, t) { n = split(s, a, " "); for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                   return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
  END { printf "CPU per particle-step: A %.4g us, B %.4g us (medians), A / B = %.3g\n",
               med(v["A"]), med(v["B"]), med(v["A"]) / med(v["B"]) }' "$TMP/all.csv"
