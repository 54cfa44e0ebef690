# Value bands of the isph_cavity quick tier (issue 15, section 2), sourced by all_done.sh: the values
# the quick tier measured for each viscous Laplacian (deterministic: one OpenMP thread, no random
# input; dx = 0.05, Re = 1000, t_end = 0.5) with tolerances for floating-point differences between builds that a
# defect exceeds: 3 % on the kinetic energy and the profile extrema (VISC-02's ke is half the
# others' here: a Laplacian defect of that size or a wrong wall velocity moves them by far more),
# 10 % on div_rms.
expect_band isph_cavity ke "visc=visc01" 0.0016095 4.8e-05
expect_band isph_cavity ux_min "visc=visc01" -0.03034 0.00091
expect_band isph_cavity uy_max "visc=visc01" 0.013485 0.0004
expect_band isph_cavity uy_min "visc=visc01" -0.013986 0.00042
expect_band isph_cavity div_rms "visc=visc01" 0.019566 0.002
expect_band isph_cavity ke "visc=visc02" 0.0007686 2.3e-05
expect_band isph_cavity ux_min "visc=visc02" -0.023719 0.00071
expect_band isph_cavity uy_max "visc=visc02" 0.0088058 0.00026
expect_band isph_cavity uy_min "visc=visc02" -0.014382 0.00043
expect_band isph_cavity div_rms "visc=visc02" 0.011244 0.0011
expect_band isph_cavity ke "visc=visc03" 0.0016023 4.8e-05
expect_band isph_cavity ux_min "visc=visc03" -0.02978 0.00089
expect_band isph_cavity uy_max "visc=visc03" 0.013448 0.0004
expect_band isph_cavity uy_min "visc=visc03" -0.013526 0.00041
expect_band isph_cavity div_rms "visc=visc03" 0.019669 0.002
expect_band isph_cavity ke "visc=visc04" 0.0016048 4.8e-05
expect_band isph_cavity ux_min "visc=visc04" -0.029942 0.0009
expect_band isph_cavity uy_max "visc=visc04" 0.013482 0.0004
expect_band isph_cavity uy_min "visc=visc04" -0.013648 0.00041
expect_band isph_cavity div_rms "visc=visc04" 0.019622 0.002
