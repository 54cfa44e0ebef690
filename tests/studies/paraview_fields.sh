#!/usr/bin/env bash
# CI check of the particle snapshots for ParaView (issue 16 part 1; docs/fields.md). Runs a short
# Taylor-Green job (tests/studies/fields_tgv.toml) and a short cylinder job
# (tests/studies/fields_cylinder.toml) through the runner into a fresh database, then opens each
# job's particles.pvd in ParaView's pvpython under xvfb-run -a (tests/studies/paraview_fields.py):
# the reader, the number of time steps (from t_end / output_interval), the final time, the point
# count of every snapshot (Taylor-Green: n_side^2; cylinder: the job's n_particles metric, its
# fluid count computed here from the box lattice and the cylinder), the array names, and a
# rendered PNG. Also reads the jobs' HDF5 files with h5py: the series the report reads are there
# and the root attributes are typed and carry the job key (issue 16 part 2).
# Skipped (exit 77) only when pvpython, xvfb-run or h5py are missing; scripts/install_deps.sh
# --with-paraview installs them. Usage: paraview_fields.sh RUNNER SRC [PNG_DIR]
RUNNER="$1" SRC="$2" PNG_DIR="${3:-}"
source "$(dirname "$0")/lib.sh"
HERE="$SRC/tests/studies"
PY=/usr/bin/python3 # Debian's, with python3-h5py (not a python3 earlier on PATH)

for tool in pvpython xvfb-run; do
  command -v "$tool" >/dev/null ||
    { echo "SKIP: $tool is not installed (Debian packages paraview python3-paraview xvfb; scripts/install_deps.sh --with-paraview installs them)"; exit 77; }
done
"$PY" -c "import h5py" 2>/dev/null ||
  { echo "SKIP: h5py is not installed (Debian package python3-h5py; scripts/install_deps.sh --with-paraview installs it)"; exit 77; }

for s in fields_tgv fields_cylinder; do
  "$RUNNER" "$HERE/$s.toml" --db "$DB" -j 2 --progress plain >"$TMP/$s.log" 2>&1 ||
    { cat "$TMP/$s.log"; fail "$s exited non-zero"; }
done
[ "$(q "SELECT count(*) FROM jobs WHERE state = 'done'")" = 2 ] || fail "expected 2 done jobs"
key() { q "SELECT job FROM job_metrics WHERE study = '$1' LIMIT 1"; }
metric() { q "SELECT value FROM job_metrics WHERE study = '$1' AND metric = '$2'"; }
int() { awk -v x="$1" 'BEGIN { printf "%d", x }'; }

# pv PVD ARGS...: the pvpython check under xvfb-run -a. Passes when the script printed its
# "PVD: OK" line, fails on any failed check. On this project's machines the X server now and then
# resets a new client's connection (ParaView then aborts with "bad X server connection" before it
# draws anything) or fails a GLX call; only such an X failure without a result is retried, at most
# 5 times.
pv() {
  local attempt
  for attempt in 1 2 3 4 5; do
    xvfb-run -a pvpython "$HERE/paraview_fields.py" "$@" >"$TMP/pv.log" 2>&1
    if grep -qxF "$1: OK" "$TMP/pv.log"; then
      grep -E '^(ok|FAIL) ' "$TMP/pv.log"
      return 0
    fi
    if grep -q '^FAIL ' "$TMP/pv.log" ||
      ! grep -qE 'bad X server connection|X Error of failed request' "$TMP/pv.log"; then
      cat "$TMP/pv.log"
      return 1
    fi
    echo "  (X server failure before pvpython's result, attempt $attempt: retrying)"
  done
  cat "$TMP/pv.log"
  return 1
}

# Taylor-Green: every particle is fluid, n_side^2 of them.
tgv="$TMP/fields_tgv/$(key fields_tgv)"
[ -f "$tgv/particles.pvd" ] || fail "no particles.pvd in $tgv"
[ "$(int "$(metric fields_tgv n_particles)")" = 900 ] || fail "taylor_green: n_particles is not 30^2"
pv "$tgv/particles.pvd" "$TMP/tgv.png" 5 0.2 900 900 || fail "ParaView check of the Taylor-Green series"

# Cylinder: fluid on the box lattice (D/dx = 5, 19 D x 16 D, centre (9 D, 8 D)) outside the
# cylinder, plus the cylinder's wall rings; every snapshot holds both kinds.
cyl="$TMP/fields_cylinder/$(key fields_cylinder)"
n_cyl="$(int "$(metric fields_cylinder n_particles)")"
fluid_cyl="$(awk 'BEGIN { dx = 0.2; n = 0; for (i = 0; i < 95; i++) for (j = 0; j < 80; j++) {
  x = (i + 0.5) * dx - 9; y = (j + 0.5) * dx - 8; if (x * x + y * y >= 0.25) n++ } print n }')"
[ "$(int "$(metric fields_cylinder n_fluid)")" = "$fluid_cyl" ] ||
  fail "cylinder: n_fluid $(metric fields_cylinder n_fluid), the lattice gives $fluid_cyl"
[ "$n_cyl" -gt "$fluid_cyl" ] || fail "cylinder: no wall particles ($n_cyl particles, $fluid_cyl fluid)"
pv "$cyl/particles.pvd" "$TMP/cylinder.png" 5 2.0 "$n_cyl" "$fluid_cyl" ||
  fail "ParaView check of the cylinder series"

# The HDF5 outputs the report reads, with typed root attributes and the job key (h5py).
"$PY" - "$tgv/taylor_green.h5" "$(key fields_tgv)" "$cyl/cylinder_free_stream.h5" \
  "$(key fields_cylinder)" "$fluid_cyl" <<'PYEOF' || fail "HDF5 outputs (h5py)"
import sys
import h5py
import numpy as np
tgv, tgv_key, cyl, cyl_key, fluid = sys.argv[1:6]
ok = True
def check(c, what):
    global ok
    print(("ok   " if c else "FAIL ") + what)
    ok = ok and c
with h5py.File(tgv, "r") as f:
    a = f.attrs
    check(isinstance(a["n_side"], np.integer) and a["n_side"] == 30, "taylor_green.h5: n_side is the integer 30")
    check(isinstance(a["Re"], np.floating) and a["Re"] == 100.0, "taylor_green.h5: Re is the double 100")
    check(a["tvf"] == "limited" and isinstance(a["tvf"], str), "taylor_green.h5: tvf is the string 'limited'")
    check(a["job_key"] == tgv_key, "taylor_green.h5: job_key is the job's key")
    check(isinstance(a["kernel_correction"], np.bool_), "taylor_green.h5: kernel_correction is a boolean")
    check(len(f["series/t"]) > 1 and len(f["fields/x"]) == 900, "taylor_green.h5: series/ and fields/ as before")
with h5py.File(cyl, "r") as f:
    a = f.attrs
    check(a["job_key"] == cyl_key and a["case"] == "cylinder_free_stream", "cylinder_free_stream.h5: job_key and case")
    check(isinstance(a["D_over_dx"], np.floating) and a["D_over_dx"] == 5.0, "cylinder_free_stream.h5: D_over_dx is the double 5")
    check(len(f["series/cd"]) > 1 and len(f["fields/x"]) == int(fluid), "cylinder_free_stream.h5: series/ and fields/ as before")
sys.exit(0 if ok else 1)
PYEOF

if [ -n "$PNG_DIR" ]; then
  mkdir -p "$PNG_DIR" && cp "$TMP/tgv.png" "$TMP/cylinder.png" "$PNG_DIR/"
fi
echo "paraview fields: OK"
