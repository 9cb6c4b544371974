"""The report on the real results of this build (FDEM_REPORT_RESULTS, written
by the fast verification tier): it is written without error, the HTML is
self-contained and balanced, and no row of a study without results passes.
Studies that have not run yet simply show as NOT RUN."""
from __future__ import annotations

import os
import shutil
import sys
import unittest
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from report_checks import check_html, run_generator, summary_rows  # noqa: E402


class StudyResultsReport(unittest.TestCase):
    def test_report_on_this_builds_results(self):
        results = Path(os.environ["FDEM_REPORT_RESULTS"])
        out = Path(os.environ["FDEM_REPORT_OUT"])
        shutil.rmtree(out, ignore_errors=True)
        args = ["--results", results, "--out", out, "--no-pdf"]
        if os.environ.get("FDEM_REPORT_BUILD_INFO"):
            args += ["--build-info", os.environ["FDEM_REPORT_BUILD_INFO"]]
        p = run_generator(*args)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        print(p.stdout.strip())
        self.assertEqual(check_html(out / "index.html").errors, [])
        for rid, row in summary_rows(out / "summary.csv").items():
            if not (results / row["study"] / "values.csv").is_file():
                self.assertEqual(row["status"], "NOT RUN", rid)


if __name__ == "__main__":
    unittest.main(verbosity=2)
