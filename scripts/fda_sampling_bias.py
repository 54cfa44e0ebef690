#!/usr/bin/env python3
"""What the FDA nozzle's centreline metric reads for an exact throat flow, at a given spacing.

The case `fda_nozzle` samples the axial velocity on the axis by the Shepard interpolation with the
scheme's kernel (Wendland C2, h = 1.3 dx, support 2 h) over fluid and wall particles (walls at rest,
velocity 0): u(x) = sum_j V_j u_j W(x - r_j) / sum_j V_j W(x - r_j). In the throat (radius 2 mm)
the support is comparable to the radius, so the sample averages over the whole section. This script
places the throat's particles as solver/core/axisymmetric_duct.hpp does (body-fitted rings,
n_r = round(R / dx) lumen rings of spacing dr = R / n_r, wall rings at spacing dx beyond R,
round(2 pi rho / dx) particles per ring, odd rings turned by half a pitch), gives the lumen rings
the ring-averaged fully developed Poiseuille profile of the benchmark's flow rate
(u = 2 U_t (1 - (rho^2 + dr^2 / 4) / R^2), U_t = 0.4143 m/s at Re_throat = 500; centre 0.829 m/s)
and prints the sampled centreline value.

Usage: scripts/fda_sampling_bias.py DX [DX ...]   (metres, e.g. 0.001 0.000666667 0.0004)
"""
import math
import sys


def wendland_c2(r, h):
    q = r / h
    return (1 - q / 2) ** 4 * (2 * q + 1) if q < 2 else 0.0


def sampled_centre(dx, R=2e-3, U_t=0.4143):
    h = 1.3 * dx
    wall_layers = math.ceil(2 * h / dx - 1e-9)
    n_r = max(1, round(R / dx))
    dr = R / n_r
    num = den = 0.0
    for s in range(-4, 5):  # slices around the sample point x = 0 (a slice boundary)
        xs = (s + 0.5) * dx
        rings = [(k, (k + 0.5) * dr, dr, 2 * U_t * (1 - ((k + 0.5) ** 2 * dr ** 2 + dr ** 2 / 4) / R ** 2))
                 for k in range(n_r)]
        rings += [(n_r + k, R + (k + 0.5) * dx, dx, 0.0) for k in range(wall_layers)]
        for k, rho, width, u in rings:
            n = max(1, round(2 * math.pi * rho / dx))
            o = 0.5 if k % 2 else 0.0
            V = dx * math.pi * ((rho + width / 2) ** 2 - (rho - width / 2) ** 2) / n
            for j in range(n):
                phi = (j + o) * 2 * math.pi / n
                w = V * wendland_c2(math.sqrt(xs ** 2 + rho ** 2), h)  # |x - r_j|, any phi
                num += w * u
                den += w
    return num / den, 2 * U_t


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for a in sys.argv[1:]:
        dx = float(a)
        got, exact = sampled_centre(dx)
        print(f"dx = {dx * 1e3:.3f} mm: sampled centre {got:.3f} m/s, exact {exact:.3f} ({got / exact - 1:+.1%})")
