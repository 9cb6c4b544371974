"""Unit tests of the report generator: verdicts, Pareto front and fitted
order, malformed inputs stop it with exit 2 naming file and line, and
FORMATS.md names every file and column the code reads. Fast: no drawing."""
from __future__ import annotations

import math
import shutil
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from report_checks import FIXTURES, REPORTS, run_generator  # noqa: E402

sys.path.insert(0, str(REPORTS))
from fdem_report import formats, plugins  # noqa: E402
from fdem_report.figures import fitted_order, pareto_front  # noqa: E402
from fdem_report.inputs import Reference, StudyResults  # noqa: E402
from fdem_report.provenance import fnv1a64, staleness  # noqa: E402
from fdem_report.summary import CONSISTENT, FAIL, INFO, MISMATCH, NOT_RUN, PASS, STALE, judge  # noqa: E402
from fdem_report.verdicts import vv20_rows  # noqa: E402

plugins.register(REPORTS.parent)  # the studies' own files and plots (verification/<study>/report_figures.py)


def ref(value, tol, kind, rid="s.q", row_class="verification", u_ref=None):
    return Reference("s", rid, "q", "m", value, tol, kind, True, "src", "prov", Path("s.csv"), 2, row_class, u_ref)


def ran(values, tier="fast"):
    return StudyResults("s", Path("."), {"study": "s", "tier": tier, "wall_time_s": 1.0, "passed": True}, values)


class Classes(unittest.TestCase):
    def test_consistency_rows_are_never_pass_or_fail(self):
        self.assertEqual(judge(ref(58, 0.5, "abs", row_class="consistency"), ran({"s.q": 58.2})).status, CONSISTENT)
        self.assertEqual(judge(ref(58, 0.5, "abs", row_class="consistency"), ran({"s.q": 59})).status, MISMATCH)
        self.assertEqual(judge(ref(58, 0.5, "abs", row_class="validation"), ran({"s.q": 59})).status, FAIL)

    def test_one_sided_tolerances(self):
        self.assertEqual(judge(ref(1.01, 0.0, "at_least"), ran({"s.q": 3.0})).status, PASS)
        self.assertEqual(judge(ref(1.01, 0.0, "at_least"), ran({"s.q": 1.009})).status, FAIL)
        self.assertEqual(judge(ref(2.0, 0.2, "at_least"), ran({"s.q": 1.81})).status, PASS)
        self.assertEqual(judge(ref(1.0, 0.6, "at_most"), ran({"s.q": -5.0})).status, PASS)
        self.assertEqual(judge(ref(1.0, 0.6, "at_most"), ran({"s.q": 1.7})).status, FAIL)

    def test_stale_results_are_shown_not_judged(self):
        row = judge(ref(1.0, 0.5, "rel"), ran({"s.q": 9.0}), stale="STALE: results of commit a, report for b")
        self.assertEqual((row.status, row.ours), (STALE, 9.0))

    def test_staleness_from_commit_and_missing_provenance(self):
        root = Path(".")
        self.assertEqual(staleness({"commit": "abc1234def"}, "abc1234def", root), "")
        self.assertEqual(staleness({"commit": "abc1234"}, "abc1234def", root), "")  # abbreviated
        self.assertIn("results of commit 0000", staleness({"commit": "0000"}, "abc1234", root))
        self.assertIn("names no commit", staleness({"study": "s"}, "abc1234", root))
        self.assertEqual(staleness({"study": "s"}, None, root), "")  # no git: nothing to check

    def test_scene_hash_is_fnv1a64_as_the_cpp_writer(self):
        with tempfile.TemporaryDirectory() as d:
            p = Path(d) / "abc.txt"
            p.write_bytes(b"abc")
            self.assertEqual(fnv1a64(p), "e71fa2190541574b")  # as verification/support/test_study_support.cpp

    def test_vv20_comparison_error_and_validation_uncertainty(self):
        results = ran({"s.q": 0.0646, "s.q.u_num": 3e-5})
        row = judge(ref(0.058, 0.103, "rel", row_class="validation", u_ref=0.000289), results)
        (v,) = vv20_rows([row])
        self.assertAlmostEqual(v["E"], 0.0066, places=12)
        self.assertAlmostEqual(v["u_val"], math.hypot(3e-5, 0.000289), places=15)
        self.assertIn("beyond the uncertainties", v["reading"])
        self.assertIn("not estimated: u_input", v["reading"])
        self.assertEqual(vv20_rows([judge(ref(1.0, 0.1, "rel"), ran({"s.q": 1.0}))]), [])  # verification: none


class Verdicts(unittest.TestCase):
    def test_relative_tolerance_passes_inside_and_fails_outside(self):
        self.assertEqual(judge(ref(0.1, 0.05, "rel"), ran({"s.q": 0.1049})).status, PASS)
        self.assertEqual(judge(ref(0.1, 0.05, "rel"), ran({"s.q": 0.1051})).status, FAIL)
        self.assertEqual(judge(ref(-0.1, 0.05, "rel"), ran({"s.q": -0.1051})).status, FAIL)

    def test_deviation_exactly_at_tolerance_passes(self):
        self.assertEqual(judge(ref(2.0, 0.25, "abs"), ran({"s.q": 2.25})).status, PASS)
        self.assertEqual(judge(ref(6.37, 0.05, "pct_points"), ran({"s.q": 6.32})).status, PASS)

    def test_absolute_and_percentage_point_tolerances(self):
        self.assertEqual(judge(ref(2.0, 0.2, "abs"), ran({"s.q": 1.7})).status, FAIL)
        self.assertEqual(judge(ref(6.37, 0.05, "pct_points"), ran({"s.q": 6.43})).status, FAIL)

    def test_non_finite_value_fails(self):
        self.assertEqual(judge(ref(1.0, 0.5, "rel"), ran({"s.q": math.nan})).status, FAIL)
        self.assertEqual(judge(ref(1.0, 0.5, "rel"), ran({"s.q": math.inf})).status, FAIL)

    def test_missing_study_or_value_is_not_run_never_pass(self):
        self.assertEqual(judge(ref(1.0, 0.5, "rel"), None).status, NOT_RUN)
        self.assertEqual(judge(ref(1.0, 0.5, "rel"), StudyResults("s", Path("."))).status, NOT_RUN)
        row = judge(ref(1.0, 0.5, "rel"), ran({"s.other": 1.0}))
        self.assertEqual(row.status, NOT_RUN)
        self.assertIn("tier fast", row.note)

    def test_row_without_tolerance_is_info(self):
        self.assertEqual(judge(ref(1.0, None, ""), ran({"s.q": 7.0})).status, INFO)

    def test_deviation_signed_and_relative_to_reference(self):
        row = judge(ref(0.110, 0.05, "rel"), ran({"s.q": 0.125}))
        self.assertAlmostEqual(row.dev_abs, 0.015, places=12)
        self.assertAlmostEqual(row.dev_pct, 100 * 0.015 / 0.110, places=9)


class Geometry(unittest.TestCase):
    def test_pareto_front_keeps_only_undominated_points(self):
        cost = [0.5, 2.0, 6.5, 20.0, 5.0]
        err = [0.05, 0.004, 0.0035, 0.003, 0.010]  # the 5th is slower and worse than the 2nd
        self.assertEqual(list(pareto_front(cost, err)), [0, 1, 2, 3])

    def test_rows_figure_scales_each_deviation_by_its_tolerance(self):
        from fdem_report.figures import rows_figure
        rows = [judge(ref(10.0, 0.1, "rel", "s.a"), ran({"s.a": 10.5})),   # half the tolerance: PASS
                judge(ref(0.0, 2.0, "abs", "s.b"), ran({"s.b": -6.0})),    # three tolerances off: FAIL
                judge(ref(1.01, 0.0, "at_least", "s.c"), ran({"s.c": 2.02})),
                judge(ref(1.0, None, "", "s.d"), ran({"s.d": 5.0}))]       # INFO: not drawn
        plots = rows_figure("s", rows)
        self.assertEqual(len(plots), 1)
        two_sided, one_sided = plots[0].fig.axes[:2]
        self.assertEqual([round(b.get_width(), 12) for b in two_sided.containers[0]], [0.5, -3.0])
        self.assertEqual([round(b.get_width(), 12) for b in one_sided.containers[0]], [2.0])
        self.assertEqual(rows_figure("s", [judge(ref(1.0, 0.1, "rel"), None)]), [])  # nothing ran: no figure

    def test_fitted_order_recovers_power_law(self):
        h = [0.1, 0.05, 0.025, 0.0125]
        self.assertAlmostEqual(fitted_order(h, [3 * x ** 2 for x in h]), 2.0, places=10)
        self.assertIsNone(fitted_order([0.1], [1.0]))


class MalformedInput(unittest.TestCase):
    """Each case corrupts one fixture file; the generator must exit 2 and name file:line."""

    def setUp(self):
        self.tmp = Path(tempfile.mkdtemp(prefix="fdem_report_"))
        shutil.copytree(FIXTURES, self.tmp / "fx")
        self.results = self.tmp / "fx" / "results"
        self.refs = self.tmp / "fx" / "reference_data"

    def tearDown(self):
        shutil.rmtree(self.tmp, ignore_errors=True)

    def generate(self):
        return run_generator("--results", self.results, "--reference-dir", self.refs,
                             "--out", self.tmp / "out", "--no-pdf")

    def expect_exit_2(self, path: Path, where: str):
        p = self.generate()
        self.assertEqual(p.returncode, 2, p.stdout + p.stderr)
        self.assertIn(f"{path}{where}", p.stderr)
        self.assertFalse((self.tmp / "out" / "index.html").exists(), "no report may be written")
        return p.stderr

    def replace_line(self, path: Path, lineno: int, text: str):
        lines = path.read_text().splitlines()
        lines[lineno - 1] = text
        path.write_text("\n".join(lines) + "\n")

    def test_non_number_in_values_exits_2_naming_file_and_line(self):
        path = self.results / "settling" / "values.csv"
        self.replace_line(path, 3, "settling.vt_twoway_vs_exp.d0.760mm,0.12x")
        self.assertIn("is not a number", self.expect_exit_2(path, ":3:"))

    def test_ragged_row_in_series_exits_2_naming_file_and_line(self):
        path = self.results / "settling" / "series_d0.208mm.csv"
        self.replace_line(path, 4, "0.04,0.01,0.01")
        self.assertIn("ragged row", self.expect_exit_2(path, ":4:"))

    def test_wrong_header_exits_2_naming_file_and_line(self):
        path = self.results / "channel" / "profile_bed.csv"
        self.replace_line(path, 1, "z_mm,u_mps")
        self.assertIn("wrong header", self.expect_exit_2(path, ":1:"))

    def test_unknown_column_exits_2(self):
        path = self.results / "dem" / "energy.csv"
        self.replace_line(path, 1, "dt_s,energy_error_rel,colour")
        self.assertIn("unknown column 'colour'", self.expect_exit_2(path, ":1:"))

    def test_reference_row_with_bad_tolerance_kind_exits_2(self):
        path = self.refs / "fluid.csv"
        self.replace_line(path, 2, "fluid.mms_velocity_order,velocity L2 order,-,2.0,0.2,relative,yes,P1 theory,x")
        self.assertIn("tolerance_kind", self.expect_exit_2(path, ":2:"))

    def test_reference_header_must_be_exact(self):
        path = self.refs / "dem.csv"
        self.replace_line(path, 1, "id,quantity,unit,value,tolerance,tolerance_kind,gate,source")
        self.expect_exit_2(path, ":1:")

    def test_invalid_meta_json_exits_2(self):
        path = self.results / "plume" / "meta.json"
        path.write_text('{"study": "plume", "tier": "fast",\n "wall_time_s": 1.0, "passed": yes}\n')
        self.expect_exit_2(path, ":2:")

    def test_fluid_speed_not_a_full_grid_exits_2(self):
        path = self.results / "plume" / "fluid_speed_twoway_t0.50s.csv"
        lines = path.read_text().splitlines()
        path.write_text("\n".join(lines[:-1]) + "\n")  # drop one grid point
        self.assertIn("full regular grid", self.expect_exit_2(path, ":"))


class FormatsDocumented(unittest.TestCase):
    def test_formats_md_names_every_file_and_column(self):
        doc = (REPORTS / "FORMATS.md").read_text()
        for study, files in formats.PATTERNS.items():
            self.assertIn(f"## {study}", doc)
            for _, schema, template in files:
                self.assertIn(f"`{template}", doc, f"{study}: {template}")
                for c in schema.required + schema.optional:
                    self.assertIn(f"`{c.name}`", doc, f"{study}/{template}: column {c.name}")

    def test_fixtures_cover_every_file_kind(self):
        # Of every study the fixture report draws (a fixture folder); a study
        # module without one (the dense-regime studies) is drawn on real results only.
        import re
        drawn = [s for s in formats.PATTERNS if (FIXTURES / "results" / s).is_dir()]
        self.assertGreaterEqual(len(drawn), 9)
        for study in drawn:
            files = formats.PATTERNS[study]
            names = [p.name for p in (FIXTURES / "results" / study).iterdir()]
            for regex, _, template in files:
                self.assertTrue(any(re.fullmatch(regex, n) for n in names), f"fixture lacks {study}/{template}")


if __name__ == "__main__":
    unittest.main(verbosity=2)
