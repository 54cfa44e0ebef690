# Value bands of the fsi_beam quick tier (issue 18; docs/fsi.md), sourced by all_done.sh: the Turek
# & Hron FSI2 set-up at 2 particles across the beam (D / dx = 10), t = 0.3 of a 0.5 ramp, coupled
# and with the beam held rigid (deterministic: one OpenMP thread). The values are those the run
# measured (also FsiBeam.ShortCoupledRunAgainstTheRigidBeam, tests/solver/test_fsi.cpp): C_D at
# t_end 4.3819 (coupled) and 4.3275 (rigid beam), within 3 %; the tip displacement (-1.121e-3,
# -0.888e-3) D (the ambient pressure squeezes the beam, the channel's asymmetry bends it down)
# within 15 %: a sign or factor of the force handed to the solid moves it by 100 % or more
# (scripts/mutations.txt, fsi_*); the rigid beam's tip does not move.
expect_band fsi_beam cd_end rigid_beam=0 4.3819 0.13
expect_band fsi_beam cd_end rigid_beam=1 4.3275 0.13
expect_band fsi_beam tip_dx_end rigid_beam=0 -0.001121 0.00017
expect_band fsi_beam tip_dy_end rigid_beam=0 -0.000888 0.00013
expect_band fsi_beam tip_dx_end rigid_beam=1 0 0
expect_band fsi_beam solid_substeps_mean rigid_beam=0 7.8 0.5
