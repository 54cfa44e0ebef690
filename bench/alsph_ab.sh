#!/usr/bin/env bash
# A B A B comparison of two runner binaries on ALSPH steps (issue 21, part 2): the flow past a
# cylinder in the paper's channel (14 D x 13 D, Re = 200) at D/dx = 20, dt U/dx = 5.08e-2, STEPS
# steps from the smooth start (ramp_time = 2, the Re = 200 studies' setting: from the impulsive
# start this step diverges after about 22 steps, which then ended every run early), both
# algorithms, one thread, each run in a fresh database. Prints, per run, the process CPU per
# particle and step and per particle and inner iteration (the job's own metrics) and the steps
# done, then the median ratios A / B.
#   bench/alsph_ab.sh OLD_RUNNER NEW_RUNNER [STEPS] [REPEATS]
# B_PARAMS='coefficients = "float"' adds TOML parameter lines to NEW_RUNNER's jobs only (the same
# binary twice then compares two options in one run).
# LONG_STEPS=N (> STEPS) also runs every job for N steps, alternated with the short one, and prints
# the steady-state step: (CPU of N steps - CPU of STEPS steps) / (N - STEPS), per particle, which
# leaves out what a run pays once (set-up, the first touch of the pair arrays).
# D_OVER_DX=N sets the resolution (default 20). Tiny size (seconds; the test bench_alsph_ab):
#   D_OVER_DX=5 LONG_STEPS=4 bench/alsph_ab.sh build/runner build/runner 2 1
set -euo pipefail
A="$1" B="$2" STEPS="${3:-40}" REPEATS="${4:-2}" D_OVER_DX="${D_OVER_DX:-20}"
LENGTHS="$STEPS${LONG_STEPS:+ $LONG_STEPS}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
for n in $LENGTHS; do
  t_end=$(awk -v n="$n" -v d="$D_OVER_DX" 'BEGIN { printf "%.10g", n * 5.08e-2 / d }')
  for alg in 1 2; do
    for who in A B; do
      extra=""; [ "$who" = B ] && extra="${B_PARAMS:-}"
      cat >"$TMP/ab$who$alg-$n.toml" <<TOML
[study]
name = "alsph_ab"
case = "cylinder_channel"
scheme = "alsph"
[params]
Re = 200
D_over_dx = $D_OVER_DX
dt_star = 5.08e-2
t_end = $t_end
algorithm = $alg
ramp_time = 2
$extra
TOML
    done
  done
done
export OMP_NUM_THREADS=1
echo "binary,algorithm,run,cpu_us_per_particle_step,iteration_cpu_us_per_particle,iterations_mean,steps"
for r in $(seq "$REPEATS"); do
  for alg in 1 2; do
    for n in $LENGTHS; do
      for who in A B; do
        bin="$A"; [ "$who" = B ] && bin="$B"
        db="$TMP/$who$alg-$n-$r.sqlite"
        "$bin" "$TMP/ab$who$alg-$n.toml" --db "$db" -j 1 --progress plain >"$db.log" 2>&1 ||
          { cat "$db.log" >&2; echo "alsph_ab.sh: $bin failed (log above)" >&2; exit 1; }
        "$bin" query --db "$db" "SELECT '$who', $alg, $r,
            max(CASE WHEN metric = 'cpu_us_per_particle_step' THEN value END),
            max(CASE WHEN metric = 'iteration_cpu_us_per_particle' THEN value END),
            max(CASE WHEN metric = 'iterations_mean' THEN value END),
            max(CASE WHEN metric = 'steps' THEN value END)
          FROM job_metrics" | tail -n +2
      done
    done
  done
done | tee "$TMP/all.csv"
awk -F, -v s="$STEPS" -v l="${LONG_STEPS:-0}" '
  { k = $1 FS $2 FS ($7 + 0); v[k] = v[k] " " $4; w[k] = w[k] " " $5 }
  function med(x,   a, n, i, j, t) { n = split(x, a, " "); for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                   return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
  function steady(who, alg) { return (med(v[who FS alg FS l]) * l - med(v[who FS alg FS s]) * s) / (l - s) }
  END { for (alg = 1; alg <= 2; ++alg) {
          printf "algorithm %d, %d steps: step %.3gx, inner iteration %.3gx (A / B, medians)\n", alg, s,
                 med(v["A" FS alg FS s]) / med(v["B" FS alg FS s]), med(w["A" FS alg FS s]) / med(w["B" FS alg FS s])
          if (l > s)
            printf "algorithm %d, steady state (steps %d..%d): A %.3g, B %.3g CPU us per particle-step: %.3gx\n",
                   alg, s + 1, l, steady("A", alg), steady("B", alg), steady("A", alg) / steady("B", alg) } }' "$TMP/all.csv"
