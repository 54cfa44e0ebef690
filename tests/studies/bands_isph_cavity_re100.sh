# Value bands of the isph_cavity_re100 quick tier (issue 15, section 2), sourced by all_done.sh: the values
# the quick tier measured for each viscous Laplacian (deterministic: one OpenMP thread, no random
# input; dx = 0.05, Re = 100, t_end = 1) with tolerances for floating-point differences between builds that a
# defect exceeds: 3 % on the kinetic energy and the profile extrema (VISC-02's ke is half the
# others' here: a Laplacian defect of that size or a wrong wall velocity moves them by far more),
# 10 % on div_rms.
expect_band isph_cavity_re100 ke "visc=visc01" 0.020032 0.0006
expect_band isph_cavity_re100 ux_min "visc=visc01" -0.14062 0.0042
expect_band isph_cavity_re100 uy_max "visc=visc01" 0.07478 0.0022
expect_band isph_cavity_re100 uy_min "visc=visc01" -0.092438 0.0028
expect_band isph_cavity_re100 div_rms "visc=visc01" 0.085268 0.0085
expect_band isph_cavity_re100 ke "visc=visc02" 0.018622 0.00056
expect_band isph_cavity_re100 ux_min "visc=visc02" -0.12904 0.0039
expect_band isph_cavity_re100 uy_max "visc=visc02" 0.077402 0.0023
expect_band isph_cavity_re100 uy_min "visc=visc02" -0.085235 0.0026
expect_band isph_cavity_re100 div_rms "visc=visc02" 0.081908 0.0082
expect_band isph_cavity_re100 ke "visc=visc03" 0.020085 0.0006
expect_band isph_cavity_re100 ux_min "visc=visc03" -0.14337 0.0043
expect_band isph_cavity_re100 uy_max "visc=visc03" 0.073927 0.0022
expect_band isph_cavity_re100 uy_min "visc=visc03" -0.095368 0.0029
expect_band isph_cavity_re100 div_rms "visc=visc03" 0.088696 0.0089
expect_band isph_cavity_re100 ke "visc=visc04" 0.020045 0.0006
expect_band isph_cavity_re100 ux_min "visc=visc04" -0.14049 0.0042
expect_band isph_cavity_re100 uy_max "visc=visc04" 0.074431 0.0022
expect_band isph_cavity_re100 uy_min "visc=visc04" -0.092127 0.0028
expect_band isph_cavity_re100 div_rms "visc=visc04" 0.088231 0.0088
