#!/usr/bin/env python3
"""The FDA benchmark nozzle's PIV data at throat Reynolds number 500, sudden-expansion orientation,
reduced to what the case fda_nozzle compares with.

Source: U.S. Food and Drug Administration, Computational Round Robin #1 (nozzle), data sets
version 2.0, P. Hariharan and R. A. Malinauskas, doi:10.17917/C78G69, file Nozzle/Data/
SE_exp_0500.zip of github.com/OSEL-DAM/CFD-and-Blood-Damage-Benchmarks; the measurements of
Hariharan et al., J. Biomech. Eng. 133 (2011) 041002. A work of the U.S. Government, public domain
(17 U.S.C. 105). Five data sets (three laboratories, repeated runs), each a conformance-converted
text file: the centreline axial velocity at up to 15 stations z and the axial velocity across the
diameter at 12 sections; z = 0 is the sudden expansion, flow towards +z, units m and m/s.

Reduction (this script; the derived tables are modified from the original, as its licence note
asks us to say):
  centreline  for every station z: the mean over the data sets that have it, their minimum and
              maximum, and how many there are;
  profiles    at every section z, each data set's profile folded to r >= 0 (the mean of its
              values at +r and -r, each side linearly interpolated) on the grid r = 0, 0.25 mm,
              ... up to the wall radius at z, then the mean over the data sets; points where a
              data set does not reach are left out of its mean.

Usage: scripts/fda_piv_extract.py SE_exp_0500.zip
Writes studies/reference/fda_piv_re500_centreline.csv, studies/reference/fda_piv_re500_profiles.csv
(described in studies/reference/README_fda_piv.md) and solver/data/fda_piv_re500.hpp (the same
numbers for the case).
"""
import io
import sys
import zipfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def wall_radius(z):
    """The benchmark's lumen radius at z (m): 6 mm inlet, 10 degree half-angle cone to the 2 mm
    throat from z = -62.685 mm to -40 mm, throat to the sudden expansion at z = 0, 6 mm after."""
    if z < -0.062685:
        return 0.006
    if z < -0.040:
        return 0.006 - (z + 0.062685) * (0.004 / 0.022685)
    if z < 0.0:
        return 0.002
    return 0.006


def parse(text):
    centre, profiles = [], {}
    lines = iter(text.splitlines())
    for line in lines:
        s = line.strip()
        if not s.startswith("plot-"):
            continue
        name = s.split()
        n = int(next(lines).strip())
        rows = [tuple(map(float, next(lines).split()[:2])) for _ in range(n)]
        if name[0] == "plot-z-distribution-axial-velocity":
            centre = rows
        elif name[0] == "plot-profile-axial-velocity-at-z":
            profiles[round(float(name[1]), 5)] = rows
    return centre, profiles


def interp(rows, r):
    """Linear interpolation of sorted (x, u) rows at r; None outside."""
    for (x0, u0), (x1, u1) in zip(rows, rows[1:]):
        if x0 <= r <= x1 and x1 > x0:
            return u0 + (u1 - u0) * (r - x0) / (x1 - x0)
    return None


def main(zip_path):
    sets = []
    with zipfile.ZipFile(zip_path) as z:
        for name in sorted(z.namelist()):
            if name.endswith(".txt"):
                sets.append((Path(name).stem.split("_")[-1],
                             parse(io.TextIOWrapper(z.open(name)).read())))
    # Centreline.
    stations = sorted({round(zz, 5) for _, (c, _) in sets for zz, _ in c})
    centre = []
    for zz in stations:
        v = [u for _, (c, _) in sets for z2, u in c if abs(z2 - zz) < 1e-7]
        centre.append((zz, sum(v) / len(v), min(v), max(v), len(v)))
    # Profiles.
    sections = sorted({zz for _, (_, p) in sets for zz in p})
    prof = []
    for zz in sections:
        R = wall_radius(zz)
        k = 0
        while k * 0.00025 <= R + 1e-12:
            r = k * 0.00025
            vals = []
            for _, (_, p) in sets:
                if zz not in p:
                    continue
                rows = sorted(p[zz])
                a, b = interp(rows, r), interp(rows, -r)
                side = [u for u in (a, b) if u is not None]
                if side:
                    vals.append(sum(side) / len(side))
            if vals:
                prof.append((zz, r, sum(vals) / len(vals), min(vals), max(vals), len(vals)))
            k += 1
    ref = ROOT / "studies" / "reference"
    with open(ref / "fda_piv_re500_centreline.csv", "w") as f:
        f.write("z_m,u_mean_m_s,u_min_m_s,u_max_m_s,n_sets\n")
        for row in centre:
            f.write("%.5f,%.6f,%.6f,%.6f,%d\n" % row)
    with open(ref / "fda_piv_re500_profiles.csv", "w") as f:
        f.write("z_m,r_m,u_mean_m_s,u_min_m_s,u_max_m_s,n_sets\n")
        for row in prof:
            f.write("%.5f,%.5f,%.6f,%.6f,%.6f,%d\n" % row)
    with open(ROOT / "solver" / "data" / "fda_piv_re500.hpp", "w") as f:
        f.write("// The FDA benchmark nozzle's PIV at throat Re = 500, sudden expansion (Hariharan "
                "et al.,\n// J. Biomech. Eng. 133 (2011) 041002; FDA Round Robin #1 data sets v2.0, "
                "doi:10.17917/C78G69,\n// public domain), reduced by scripts/fda_piv_extract.py "
                "(generated; do not edit): the mean\n// over the five data sets of the centreline "
                "axial velocity and of the folded profiles\n// (studies/reference/fda_piv_re500_*.csv"
                " with their spread). z = 0: the sudden expansion; m, m/s.\n#pragma once\n\n"
                "#include <array>\n\nnamespace sph::fda_piv {\n\n")
        f.write("struct Station {\n  double z, u;\n};\nstruct ProfilePoint {\n  double z, r, u;\n};"
                "\n\n")
        f.write("inline constexpr std::array<Station, %d> centreline{{\n" % len(centre))
        for zz, u, *_ in centre:
            f.write("    {%.5f, %.6f},\n" % (zz, u))
        f.write("}};\n\n")
        f.write("inline constexpr std::array<ProfilePoint, %d> profiles{{\n" % len(prof))
        for zz, r, u, *_ in prof:
            f.write("    {%.5f, %.5f, %.6f},\n" % (zz, r, u))
        f.write("}};\n\n} // namespace sph::fda_piv\n")
    print("%d stations, %d profile points over %d sections from %d data sets"
          % (len(centre), len(prof), len(sections), len(sets)))


if __name__ == "__main__":
    main(sys.argv[1])
