#!/usr/bin/env bash
# A B A B comparison of two runner binaries on the WCSPH-TVF Taylor-Green vortex (issue 21, part
# 3): the same job (case taylor_green, scheme wcsph_tvf, n_side x n_side particles to t_end), one
# thread, alternated so that both see the same load (bench/one_ab.sh: CPU per particle and
# advection step, the median ratio A / B; above 1: B is cheaper).
#   bench/tvf_ab.sh OLD_RUNNER NEW_RUNNER [REPEATS] [N_SIDE] [T_END]   (default 3 100 0.5)
# Tiny size (a second; the test bench_tvf_ab): bench/tvf_ab.sh build/runner build/runner 1 20 0.05
set -euo pipefail
exec "$(dirname "$0")/one_ab.sh" "$1" "$2" "${3:-3}" taylor_green --scheme wcsph_tvf \
  "n_side=${4:-100}" "t_end=${5:-0.5}"
