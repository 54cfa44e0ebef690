#!/usr/bin/env bash
# CI check of scripts/isph_divergence_track.py (docs/isph.md, "VISC-02 to t = 40"): a tiny ISPH
# cavity job with particle snapshots (dx = 0.1, 0.05 time units, a snapshot every 0.01) runs
# through `runner one`; the script reads its snapshots and prints one row per snapshot, at the
# snapshots' times, with the lid-driven fluid slower than the lid, no particle pair closer than the
# 0.6 dx it counts, the lattice's spacing between fluid particles (nn_min about 1 dx after 0.05
# time units) and the wall particles at least 0.4 dx away (the lattice: 1 dx). Usage: divergence_track.sh RUNNER SRC
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
# t, speed, n(nn < 0.6 dx) of each row: times 0, 0.01, ..., 0.05; fluid below the lid's speed 1;
# none of the lattice's particles closer than 0.6 dx after 0.05 time units.
tail -n +2 "$TMP/track.txt" | awk -F, -v n="$n" '
  { t[NR] = $1
    if ($2 < 0 || $2 >= 1.0) { print "FAIL: row " NR ": fastest fluid " $2; bad = 1 }
    if ($9 != 0) { print "FAIL: row " NR ": " $9 " close pairs"; bad = 1 }
    if ($6 < 0.9 || $10 < 0.4) { print "FAIL: row " NR ": distances " $6 ", " $10; bad = 1 } }
  END { for (i = 1; i <= NR; ++i)
          if (t[i] < 0.01 * (i - 1) - 1e-9 || t[i] > 0.01 * (i - 1) + 1e-3) { print "FAIL: row " i " at t = " t[i]; bad = 1 }
        exit bad }' || fail "track rows"
echo "divergence_track: $rows rows"
