#!/usr/bin/python3
"""Smoke test of the plume sweep driver: `fdem_plume_sweep --tiny` runs, writes
plume_sweep.csv that the report's own strict reader accepts (reports/fdem_report
formats.PLUME_SWEEP), one row per (grain count, cell size) of the tiny mode,
and the numbers make physical sense.

  check_plume_sweep.py FDEM_PLUME_SWEEP OUT_DIR
"""
import math
import sys

from sweep_smoke import SmokeFailure, report, run_and_read

G = 9.81  # [m/s^2]
# Centroid depth of the initial block, from its top face: the lattice puts its
# layers at cell centres, evenly over the 40 mm height, so half of it.
CENTROID0_M = 0.02


def main() -> None:
    rows = run_and_read("--tiny", "plume_sweep.csv", "PLUME_SWEEP")[1].rows
    # Tiny mode: grains 1/64 and 1/32 of 28224 (lattice-rounded) x cells 20 and 10 mm.
    got = {(round(x["grains_fraction"] * 64), round(x["cell_nominal_mm"])) for x in rows}
    if got != {(1, 20), (1, 10), (2, 20), (2, 10)} or len(rows) != 4:
        raise SmokeFailure(f"settings {sorted(got)} are not the tiny mode's 2 x 2")
    for x in rows:
        if str(x["mode"]) != "tiny":
            raise SmokeFailure(f"mode {x['mode']} != tiny")
        # The lattice rounds the count to nx^2 nz: within 15 % of the request
        # at these small counts (441 -> 432, 882 -> 882).
        if abs(x["grains"] / (x["grains_fraction"] * 28224) - 1) > 0.15:
            raise SmokeFailure(f"grain count {x['grains']} far from {x['grains_fraction']} x 28224")
        # The solid fraction is held at the reduced scene's 4704 x 0.6 mm in
        # the 20 x 20 x 40 mm block: N pi d^3 / 6 / V = 3.325 %. 1e-5: d and
        # the fraction are written with 7 and 6 significant digits.
        phi = x["grains"] * math.pi * x["d_m"] ** 3 / 6 / (0.02 * 0.02 * 0.04)
        phi_reduced = 4704 * math.pi * 0.6e-3 ** 3 / 6 / (0.02 * 0.02 * 0.04)
        if abs(phi / x["solid_fraction"] - 1) > 1e-5 or abs(x["solid_fraction"] / phi_reduced - 1) > 1e-5:
            raise SmokeFailure(f"solid fraction {phi} (file {x['solid_fraction']}) not held at the reduced scene's 3.325 %")
        t = x["t_s"]
        if abs(t - 0.02) > 1e-9:
            raise SmokeFailure(f"end time {t} != 0.02 s")
        # From rest, a grain falls at most the free-fall distance g t^2 / 2
        # (drag and buoyancy only slow it): the centroid sinks by more than
        # nothing and less than 2 mm at 0.02 s.
        if not 0 < x["centroid_depth_m"] - CENTROID0_M < 0.5 * G * t * t:
            raise SmokeFailure(f"centroid depth {x['centroid_depth_m']} outside (0, g t^2/2) of its start")
        if not (x["peak_fluid_speed_mps"] > 0 and x["peak_fluid_speed_mps"] < G * t):
            raise SmokeFailure(f"peak fluid speed {x['peak_fluid_speed_mps']} outside (0, g t)")
        if x["grains_lost"] != 0 or not x["wall_time_s"] > 0:
            raise SmokeFailure(f"bad row {x}")
    print(f"ok: {len(rows)} runs, wall {sum(x['wall_time_s'] for x in rows):.1f} s")


if __name__ == "__main__":
    sys.exit(report("check_plume_sweep", main))
