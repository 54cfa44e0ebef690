# Value bands of the cantilever quick tier (issue 18; docs/solid.md), sourced by all_done.sh: the
# elastic solid's L/H = 10 beam at H/dx = 4 (deterministic: one OpenMP thread, t_end = 1 s, one
# whole period). The tolerances absorb floating-point differences between builds and stay far
# inside what separates resolutions (deflection ratio 1.675 / 1.174 / 1.057 at H/dx = 4 / 8 / 16)
# or what a defect of the stress moves (the mutations of scripts/mutations.txt): 2 % on the
# deflection ratio, 2 % on the frequency ratio; the damping only takes energy out (drift -1.3e-3 of
# the largest elastic energy); the internal forces and torques sum to zero to round-off (clamp
# included).
expect_band cantilever periods - 1 0
expect_band cantilever deflection_ratio - 1.6752 0.033
expect_band cantilever frequency_ratio - 0.77054 0.015
expect_band cantilever energy_drift - -0.00131 0.0005
expect_band cantilever internal_force_rel_max - 0 1e-13
expect_band cantilever internal_torque_rel_max - 0 1e-13
