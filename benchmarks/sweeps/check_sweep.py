#!/usr/bin/python3
"""Smoke test of the accuracy-cost sweep driver: `fdem_sweep --quick` runs,
writes accuracy_cost.csv that the report's own strict reader accepts
(reports/fdem_report formats.ACCURACY_COST), one row per quick setting, and
the numbers make physical sense.

  check_sweep.py FDEM_SWEEP OUT_DIR
"""
import csv
import math
import sys

from sweep_smoke import SmokeFailure, report, run_and_read


def main() -> None:
    out, table = run_and_read("--quick", "accuracy_cost.csv", "ACCURACY_COST")
    rows = table.rows
    expected = {("subcycles", "N=10"), ("subcycles", "N=100"), ("dt_fluid", "dt=0.04 s"), ("dt_fluid", "dt=0.02 s"),
                ("ratio", "r=3"), ("ratio", "r=5"), ("porosity_scheme", "centre r=3"),
                ("porosity_scheme", "shape_function r=3")}
    got = {(str(x["sweep"]), str(x["setting"])) for x in rows}
    if got != expected:
        raise SmokeFailure(f"settings {sorted(got)} != {sorted(expected)}")
    for x in rows:
        if not (math.isfinite(x["error"]) and x["error"] >= 0 and x["wall_time_s"] > 0):
            raise SmokeFailure(f"bad row {x}")
    err = {(str(x["sweep"]), str(x["setting"])): x["error"] for x in rows}
    # Cell / d = 5: the grain's element has eps >= 0.98, so the Wen & Yu factor
    # eps^-1.65 raises the drag by at most 3.4 % and the terminal velocity
    # falls by about that much; the fluid dragged along in the 16 d wide quick
    # box adds a few percent more. 10 % bounds both with margin; a larger error
    # means the coupled run no longer solves the settling model.
    if err[("ratio", "r=5")] > 0.10:
        raise SmokeFailure(f"terminal velocity error {err[('ratio', 'r=5')]:.3g} at cell/d = 5 exceeds 10 %")
    # The centre scheme's solid fraction in the grain's element grows like
    # (d / cell)^3 (Eq. 32): a coarser ratio must not be more accurate.
    if not err[("ratio", "r=3")] > err[("ratio", "r=5")]:
        raise SmokeFailure("error at cell/d = 3 is not larger than at cell/d = 5 with the centre porosity")
    # The time-step sweeps' error is the distance from a finer reference run
    # (fdem_sweep.cpp, time_reference): velocity Verlet with drag is first
    # order in dt / tau, so the coarser setting must be further from it.
    for sweep, coarse, fine in (("subcycles", "N=10", "N=100"), ("dt_fluid", "dt=0.04 s", "dt=0.02 s")):
        if not err[(sweep, coarse)] > err[(sweep, fine)] > 0:
            raise SmokeFailure(f"{sweep}: error {coarse} {err[(sweep, coarse)]:.3g} not above {fine} {err[(sweep, fine)]:.3g} > 0")
    with open(out / "sweeps" / "accuracy_cost_detail.csv", newline="") as f:
        detail = list(csv.DictReader(f))
    if len(detail) != len(rows):
        raise SmokeFailure("detail file has a different row count")
    print(f"ok: {len(rows)} settings, errors {min(err.values()):.3g} .. {max(err.values()):.3g}")


if __name__ == "__main__":
    sys.exit(report("check_sweep", main))
