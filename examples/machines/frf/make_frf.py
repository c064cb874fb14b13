#!/usr/bin/env python3
"""Writes the example tap tests of b_frf.toml: a tool measured along the lathe's x and y, as a
shop's analyser exports them, from known modes with 2 % measurement noise (seeded), so the
lobes read from them can be checked against the modes (tests/io/lobes_frf_test.cpp).

  tool_xx.csv   x response to x excitation: 250 Hz (k 2.26e8 N/m, zeta 0.012) and a stiff
                900 Hz mode (k 1.5e9 N/m, zeta 0.03); receptance, CSV
  tool_yy.uff   y response to y excitation: 150 Hz (k 2.13e8 N/m, zeta 0.010); accelerance in
                m/s^2 per N, universal file format dataset 58 (ASCII, complex double, even)
Both 40-600 Hz every 0.25 Hz.

  boring_bar_xx.csv   a slender boring bar (400 Hz, k 1.5e6 N/m, zeta 0.02, 30 deg to x) on a
                stiffer turret mode (650 Hz, k 5e6 N/m, zeta 0.03, -45 deg), measured along x (the
                radial direction): the oriented receptance sum cos^2(theta)/(k(1 - r^2 + 2j zeta r)),
                50-1000 Hz every 0.25 Hz, 2 % noise: the tap test of the Python notebook
                examples/notebooks/tap_test_to_stable_cut.ipynb (the tool of
                tests/systems/b_structure_test.cpp).
Run from this folder: python3 make_frf.py
"""
import cmath
import math
import random

XX = [(2.26e8, 0.012, 250.0), (1.5e9, 0.03, 900.0)]
YY = [(2.13e8, 0.010, 150.0)]
F = [40.0 + 0.25 * k for k in range(int((600.0 - 40.0) / 0.25) + 1)]


def receptance(modes, f):
    return sum(1.0 / (k * complex(1.0 - (f / fn) ** 2, 2.0 * z * f / fn)) for k, z, fn in modes)


def noisy(h, rng, sigma=0.02):
    return h * complex(1.0 + rng.gauss(0.0, sigma), rng.gauss(0.0, sigma))


rng = random.Random(35)
with open("tool_xx.csv", "w") as out:
    out.write("# tap test of the tool tip, x response / x hammer (synthetic: make_frf.py)\n")
    out.write("frequency_Hz,real_m_per_N,imag_m_per_N\n")
    for f in F:
        h = noisy(receptance(XX, f), rng)
        out.write(f"{f:.2f},{h.real:.6e},{h.imag:.6e}\n")

# Dataset 58 (SDRC "Universal Dataset Number 58"): records as the format's Fortran formats say.
with open("tool_yy.uff", "w") as out:
    out.write("    -1\n    58\n")
    out.write("%-80s\n" % "tool tip y/y accelerance (synthetic: make_frf.py)")
    for _ in range(4):
        out.write("%-80s\n" % "NONE")
    out.write("%5d%10d%5d%10d %-10s%10d%4d %-10s%10d%4d\n" % (4, 1, 1, 0, "TOOL", 1, 2, "TOOL", 1, 2))
    out.write("%10d%10d%10d%13.5E%13.5E%13.5E\n" % (6, len(F), 1, F[0], 0.25, 0.0))
    for spec, le, fe, lab, units in [(18, 0, 0, "Frequency", "Hz"), (12, 1, 0, "Acceleration", "m/s^2"),
                                     (13, 0, 1, "Force", "N"), (0, 0, 0, "NONE", "NONE")]:
        out.write("%10d%5d%5d%5d %-20s %-20s\n" % (spec, le, fe, 0, lab, units))
    vals = []
    for f in F:
        w = 2.0 * math.pi * f
        a = noisy(-w * w * receptance(YY, f), rng)
        vals += [a.real, a.imag]
    for i in range(0, len(vals), 4):
        out.write("".join("%20.12E" % v for v in vals[i:i + 4]) + "\n")
    out.write("    -1\n")

# The boring bar of the notebook (its own generator, so the two files above stay as they were).
BAR = [(1.5e6, 0.02, 400.0, 30.0), (5e6, 0.03, 650.0, -45.0)]
BAR_X = [(k / math.cos(math.radians(a)) ** 2, z, fn) for k, z, fn, a in BAR]
rng = random.Random(36)
with open("boring_bar_xx.csv", "w") as out:
    out.write("# tap test of a boring bar, x (radial) response / x hammer (synthetic: make_frf.py)\n")
    out.write("frequency_Hz,real_m_per_N,imag_m_per_N\n")
    for k in range(int((1000.0 - 50.0) / 0.25) + 1):
        f = 50.0 + 0.25 * k
        h = noisy(receptance(BAR_X, f), rng)
        out.write(f"{f:.2f},{h.real:.6e},{h.imag:.6e}\n")
