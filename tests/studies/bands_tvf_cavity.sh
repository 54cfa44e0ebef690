# Value bands of the tvf_cavity quick tier (issue 15, section 2), sourced by all_done.sh: the
# values the quick tier measured at Re = 100 and 1000 (deterministic: one OpenMP thread; dx = 0.05,
# t_end = 1) with tolerances for floating-point differences between builds that a defect exceeds:
# 3 % on the kinetic energy and the profile extrema, 10 % on the largest density deviation (the
# weak-compressibility error, c0 = 10 U).
expect_band tvf_cavity ke "Re=100.0" 0.024728 0.00074
expect_band tvf_cavity ux_min "Re=100.0" -0.14648 0.0044
expect_band tvf_cavity uy_max "Re=100.0" 0.076692 0.0023
expect_band tvf_cavity uy_min "Re=100.0" -0.10216 0.0031
expect_band tvf_cavity density_dev_max "Re=100.0" 0.027485 0.0027
expect_band tvf_cavity ke "Re=1000.0" 0.018411 0.00055
expect_band tvf_cavity ux_min "Re=1000.0" -0.095287 0.0029
expect_band tvf_cavity uy_max "Re=1000.0" 0.064374 0.0019
expect_band tvf_cavity uy_min "Re=1000.0" -0.059244 0.0018
expect_band tvf_cavity density_dev_max "Re=1000.0" 0.024659 0.0025
