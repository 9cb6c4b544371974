"""The whole report on the hand-made fixture results: it is written, the
failing deviation is shown as FAIL and stands out, missing studies and values
are NOT RUN, every plot kind is drawn, the HTML is self-contained and balanced,
and pdftoppm renders every page of the PDF."""
from __future__ import annotations

import shutil
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from report_checks import FIXTURES, check_html, run_generator, summary_rows  # noqa: E402

FAILING_ID = "settling.vt_twoway_vs_exp.d0.760mm"  # 0.125 vs 0.110 +- 5 %: 13.6 % off
NOT_RUN_IDS = ("missing_study.anything",  # no results folder at all
               "settling.vt_oneway_vs_gsl.d0.500mm")  # study ran, value not written
# Plots the fixture feeds: settling 2, mesh 2 schemes + amplitudes, channel 1,
# plume metrics + grains for 2 modes + fluid speed for 1 mode, fluid 1, dem 2, benchmarks 4
# (accuracy-cost, trends, plume sweep, scaling).
EXPECTED_FIGURES = 2 + 3 + 1 + 4 + 1 + 2 + 4


class FixtureReport(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.tmp = Path(tempfile.mkdtemp(prefix="fdem_report_"))
        cls.out = cls.tmp / "out"
        build_info = cls.tmp / "build_info.json"
        build_info.write_text('{"version": "0.1.0", "commit": "abc1234", "build_type": "Release",'
                              ' "compiler": "GNU 12.2.0", "sanitize": "OFF"}\n')
        cls.proc = run_generator("--results", FIXTURES / "results", "--reference-dir", FIXTURES / "reference_data",
                                 "--build-info", build_info, "--out", cls.out)
        cls.html_path = cls.out / "index.html"

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.tmp, ignore_errors=True)

    def setUp(self):
        self.assertEqual(self.proc.returncode, 0, self.proc.stdout + self.proc.stderr)

    def test_counts_printed_and_files_written(self):
        self.assertIn("2 FAIL, 5 PASS, 2 NOT RUN, 2 INFO", self.proc.stdout)
        for name in ("index.html", "report.pdf", "summary.csv"):
            self.assertGreater((self.out / name).stat().st_size, 0, name)

    def test_failing_deviation_is_shown_as_fail(self):
        self.assertEqual(summary_rows(self.out / "summary.csv")[FAILING_ID]["status"], "FAIL")
        html = check_html(self.html_path)
        rows = [(cls, cells) for cls, cells in html.rows if FAILING_ID in cells]
        self.assertTrue(rows, "failing row missing from the HTML")
        for cls, cells in rows:  # summary table and the study's own table
            self.assertEqual(cls, "FAIL")
            self.assertEqual(cells[0], "FAIL")
        text = self.html_path.read_text()
        self.assertIn('class="badge b-FAIL">2 FAIL', text)  # the count at the top
        self.assertLess(text.index("2 FAIL"), text.index('id="summary"'))

    def test_missing_study_and_missing_value_are_not_run(self):
        summary = summary_rows(self.out / "summary.csv")
        html = check_html(self.html_path)
        for rid in NOT_RUN_IDS:
            self.assertEqual(summary[rid]["status"], "NOT RUN", rid)
            for cls, cells in html.rows:
                if rid in cells:
                    self.assertEqual((cls, cells[0]), ("NOTRUN", "NOT RUN"), rid)

    def test_every_plot_kind_is_drawn_and_html_is_self_contained(self):
        html = check_html(self.html_path)
        self.assertEqual(html.errors, [])
        self.assertEqual(html.images, EXPECTED_FIGURES)
        for section in ("summary", "studies", "provenance", "study-settling", "study-mesh_sensitivity",
                        "study-channel", "study-plume", "study-fluid", "study-dem", "study-benchmarks",
                        "study-hard_cases", "study-missing_study"):
            self.assertIn(section, html.ids)
        text = self.html_path.read_text()
        self.assertNotIn("not run: no ", text)  # the fixture feeds every plot
        self.assertIn("abc1234", text)  # provenance from build_info.json
        self.assertIn("notes.txt", text)  # files the report does not read are listed

    def test_pdf_renders_every_page_with_pdftoppm(self):
        pdftoppm = shutil.which("pdftoppm")
        if pdftoppm is None:
            self.fail("pdftoppm not found (Debian package poppler-utils)")
        pdf = self.out / "report.pdf"
        info = subprocess.run(["pdfinfo", str(pdf)], capture_output=True, text=True, check=True).stdout
        pages = int(next(line.split()[-1] for line in info.splitlines() if line.startswith("Pages:")))
        self.assertGreaterEqual(pages, 3 + EXPECTED_FIGURES)
        subprocess.run([pdftoppm, "-png", "-r", "12", str(pdf), str(self.tmp / "page")], check=True,
                       capture_output=True, timeout=120)
        pngs = sorted(self.tmp.glob("page-*.png"))
        self.assertEqual(len(pngs), pages)
        for png in pngs:
            self.assertEqual(png.read_bytes()[:8], b"\x89PNG\r\n\x1a\n", png)


class MissingResults(unittest.TestCase):
    def test_study_without_results_shows_not_run_notes_and_strict_exits_1(self):
        tmp = Path(tempfile.mkdtemp(prefix="fdem_report_"))
        try:
            shutil.copytree(FIXTURES / "results", tmp / "results")
            shutil.rmtree(tmp / "results" / "plume")
            p = run_generator("--results", tmp / "results", "--reference-dir", FIXTURES / "reference_data",
                              "--out", tmp / "out", "--no-pdf", "--strict")
            self.assertEqual(p.returncode, 1, p.stdout + p.stderr)  # --strict: a FAIL row exits 1
            summary = summary_rows(tmp / "out" / "summary.csv")
            self.assertEqual(summary["plume.spread_ratio_twoway_over_oneway"]["status"], "NOT RUN")
            self.assertNotIn("PASS", {r["status"] for r in summary.values() if r["study"] == "plume"})
            text = (tmp / "out" / "index.html").read_text()
            for note in ("not run: no plume/metrics_&lt;mode&gt;.csv", "not run: no plume/particles_&lt;mode&gt;",
                         "not run: no plume/fluid_speed_&lt;mode&gt;", "NOT RUN: no results in"):
                self.assertIn(note, text)
            self.assertEqual(check_html(tmp / "out" / "index.html").errors, [])
        finally:
            shutil.rmtree(tmp, ignore_errors=True)


if __name__ == "__main__":
    unittest.main(verbosity=2)
