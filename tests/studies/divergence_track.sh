#!/usr/bin/env bash
# CI check of scripts/isph_divergence_track.py (docs/isph.md, "VISC-02 to t = 40"): a tiny ISPH
# cavity job with particle snapshots (dx = 0.1, 0.05 time units, a snapshot every 0.01) runs
# through `runner one`; the script prints one row per snapshot, at the snapshots' times, and on
# this barely moved lattice: fluid slower than the lid, no pair closer than 0.6 dx, the nearest
# fluid neighbour about 1 dx away (>= 0.9) and the nearest wall particle too (>= 0.4).
# Usage: divergence_track.sh RUNNER SRC
RUNNER="$1" SRC="$2"
source "$(dirname "$0")/lib.sh"

"$RUNNER" one lid_driven_cavity --scheme isph dx=0.1 t_end=0.05 output_interval=0.01 \
  --db "$DB" --yes --threads-per-job 1 >"$TMP/one.log" 2>&1 || { cat "$TMP/one.log"; fail "runner one"; }
job="$(sed -n 's/^outputs: *\([^ ]*\)\/ (.*/\1/p' "$TMP/one.log")"
[ -d "$job/particles" ] || { cat "$TMP/one.log"; fail "no job folder with particles/ in the log"; }
n="$(ls "$job"/particles/*.vtp | wc -l)"
# Debian's python3, with numpy (python3-numpy: scripts/install_deps.sh --tests brings it with PySPH)
/usr/bin/python3 "$SRC/scripts/isph_divergence_track.py" "$job" 0.1 >"$TMP/track.txt" ||
  { cat "$TMP/track.txt"; fail "isph_divergence_track.py exited non-zero"; }
cat "$TMP/track.txt"
rows="$(tail -n +2 "$TMP/track.txt" | wc -l)"
[ "$rows" = "$n" ] || fail "expected $n rows (one per snapshot), got $rows"
# Columns: 1 t, 2 v_max, 6 nn_min, 9 n_close, 10 wall_min (the script's header).
tail -n +2 "$TMP/track.txt" | awk -F, '
  { t[NR] = $1
    if ($2 < 0 || $2 >= 1.0) { print "FAIL: row " NR ": fastest fluid " $2; bad = 1 }
    if ($9 != 0) { print "FAIL: row " NR ": " $9 " close pairs"; bad = 1 }
    if ($6 < 0.9 || $10 < 0.4) { print "FAIL: row " NR ": distances " $6 ", " $10; bad = 1 } }
  END { for (i = 1; i <= NR; ++i)
          if (t[i] < 0.01 * (i - 1) - 1e-9 || t[i] > 0.01 * (i - 1) + 1e-3) { print "FAIL: row " i " at t = " t[i]; bad = 1 }
        exit bad }' || fail "track rows"
echo "divergence_track: $rows rows"
