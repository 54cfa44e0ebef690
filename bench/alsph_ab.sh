#!/usr/bin/env bash
# A B A B comparison of two runner binaries on ALSPH steps (issue 21, part 2): the flow past a
# cylinder in the paper's channel (14 D x 13 D, Re = 200) at D/dx = 20, dt U/dx = 5.08e-2, STEPS
# steps from the smooth start (ramp_time = 2, the Re = 200 studies' setting: from the impulsive
# start this step diverges after about 22 steps, which then ended every run early), both
# algorithms, one thread, each run in a fresh database. Prints, per run, the process CPU per
# particle and step and per particle and inner iteration (the job's own metrics) and the steps
# done, then the median ratios A / B.
#   bench/alsph_ab.sh OLD_RUNNER NEW_RUNNER [STEPS] [REPEATS]
set -euo pipefail
A="$1" B="$2" STEPS="${3:-40}" REPEATS="${4:-2}"
TMP="$(mktemp -d)"
trap 'rm -rf "$TMP"' EXIT
t_end=$(awk -v n="$STEPS" 'BEGIN { printf "%.10g", n * 5.08e-2 / 20 }')
for alg in 1 2; do
  cat >"$TMP/ab$alg.toml" <<TOML
[study]
name = "alsph_ab"
case = "cylinder_channel"
scheme = "alsph"
[params]
Re = 200
D_over_dx = 20
dt_star = 5.08e-2
t_end = $t_end
algorithm = $alg
ramp_time = 2
TOML
done
export OMP_NUM_THREADS=1
echo "binary,algorithm,run,cpu_us_per_particle_step,iteration_cpu_us_per_particle,iterations_mean,steps"
for r in $(seq "$REPEATS"); do
  for alg in 1 2; do
    for who in A B; do
      bin="$A"; [ "$who" = B ] && bin="$B"
      db="$TMP/$who$alg$r.sqlite"
      "$bin" "$TMP/ab$alg.toml" --db "$db" -j 1 --progress plain >/dev/null 2>&1
      "$bin" query --db "$db" "SELECT '$who', $alg, $r,
          max(CASE WHEN metric = 'cpu_us_per_particle_step' THEN value END),
          max(CASE WHEN metric = 'iteration_cpu_us_per_particle' THEN value END),
          max(CASE WHEN metric = 'iterations_mean' THEN value END),
          max(CASE WHEN metric = 'steps' THEN value END)
        FROM job_metrics" | tail -n +2
    done
  done
done | tee "$TMP/all.csv"
awk -F, '{ v[$1 FS $2] = v[$1 FS $2] " " $4; w[$1 FS $2] = w[$1 FS $2] " " $5 }
  function med(s,   a, n, i, j, t) { n = split(s, a, " "); for (i = 1; i <= n; ++i) for (j = i + 1; j <= n; ++j) if (a[j] < a[i]) { t = a[i]; a[i] = a[j]; a[j] = t }
                                   return n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2 }
  END { for (alg = 1; alg <= 2; ++alg)
          printf "algorithm %d: step %.3gx, inner iteration %.3gx (A / B, medians)\n", alg,
                 med(v["A" FS alg]) / med(v["B" FS alg]), med(w["A" FS alg]) / med(w["B" FS alg]) }' "$TMP/all.csv"
