#!/usr/bin/python3
"""Unit tests of scaling.py: the fitted exponent, the parsing of Google
Benchmark JSON into time per step, and the CSV the report reads (its own
strict reader, reports/fdem_report formats.SCALING). No benchmark runs."""
import math
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
sys.path.insert(0, str(HERE.parents[1] / "reports"))
import scaling  # noqa: E402


def bench(name: str, real_ms: float, cpu_ms: float, **counters) -> dict:
    return {"name": name, "run_type": "iteration", "time_unit": "ms", "real_time": real_ms, "cpu_time": cpu_ms,
            "iterations": 3, "threads": 1, **counters}


class FitExponent(unittest.TestCase):
    def test_power_law_is_recovered_exactly(self):
        sizes = [1e3, 1e4, 1e5, 1e6]
        for p in (1.0, 1.25, 0.5):
            self.assertAlmostEqual(scaling.fit_exponent(sizes, [3e-8 * n ** p for n in sizes]), p, places=12)

    def test_least_squares_over_noisy_points(self):
        # Points off the power law (+-10 %): the exponent is the least-squares
        # slope in log-log (closed form), not a two-point slope.
        sizes, times = [1e3, 1e4, 1e5], [1e-5 * 1.1, 1e-4 / 1.1, 1e-3 * 1.1]
        x = [math.log(s) for s in sizes]
        y = [math.log(t) for t in times]
        mx, my = sum(x) / 3, sum(y) / 3
        slope = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x)
        self.assertAlmostEqual(scaling.fit_exponent(sizes, times), slope, places=12)

    def test_fewer_than_two_sizes_give_no_exponent(self):
        self.assertIsNone(scaling.fit_exponent([1e3], [1.0]))
        self.assertIsNone(scaling.fit_exponent([1e3, 1e3], [1.0, 2.0]))


class Parse(unittest.TestCase):
    REPORT = {"context": {"load_avg": [1.5, 1.0, 0.5]}, "benchmarks": [
        bench("BM_Scaling_DenseLattice/1000/1/min_time:0.300/real_time", 2.0, 1.9, particles=1000,
              steps_per_iteration=20, threads=1),
        bench("BM_Scaling_DenseLattice/1000/2/min_time:0.300/real_time", 1.0, 1.8, particles=1000,
              steps_per_iteration=20, threads=2),
        bench("BM_FluidStep/12/2/min_time:0.200/real_time", 30.0, 60.0, elements=8640, threads=2),
        bench("BM_SceneB_SettledBed/1/iterations:1/real_time", 9.0, 9.0),  # not a scaling case
        {"name": "BM_Scaling_Gas/1000/1/x_median", "run_type": "aggregate"},  # aggregates skipped
    ]}

    def test_time_per_step_threads_and_size_come_from_name_and_counters(self):
        rows = scaling.rows_from(self.REPORT)
        self.assertEqual([(r["case"], r["size"], r["threads"]) for r in rows],
                         [("dem_dense", 1000, 1), ("dem_dense", 1000, 2), ("fluid_step", 8640, 2)])
        self.assertAlmostEqual(rows[0]["seconds_per_step"], 2.0e-3 / 20)
        self.assertAlmostEqual(rows[1]["cpu_seconds_per_step"], 1.8e-3 / 20)
        self.assertAlmostEqual(rows[2]["seconds_per_step"], 30e-3)  # one fluid step per iteration
        self.assertEqual(rows[0]["load_average"], 1.5)

    def test_csv_is_read_by_the_reports_strict_reader(self):
        from fdem_report import csvio, formats
        rows = scaling.rows_from(self.REPORT)
        with tempfile.TemporaryDirectory() as d:
            path = Path(d) / "benchmarks" / "scaling.csv"
            scaling.write_csv(path, rows)
            table = csvio.read_table(path, formats.SCALING)
        self.assertEqual(len(table.rows), 3)
        self.assertEqual(table.rows[2]["case"], "fluid_step")
        self.assertAlmostEqual(table.rows[1]["seconds_per_step"], 5e-5)


if __name__ == "__main__":
    unittest.main(verbosity=2)
