#!/usr/bin/python3
"""Unit tests of the trend tool on fixture Google Benchmark JSON (real output of
libbenchmark 1.7.1, 3 repetitions): median of repeats, history append, the
regression verdict and its noise band, the command end to end."""
import copy
import json
import statistics
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
import trend  # noqa: E402

FIXTURE = HERE / "fixtures" / "google_benchmark_1.7.1.json"
PROV = {"run_id": "r1", "date": "2026-11-23T00:00:00Z", "commit": "aaaaaaa", "dirty": False,
        "compiler": "GNU 12.2.0", "build_type": "Release", "host": "fixture-host", "nproc": 2,
        "cpu_model": "AMD EPYC"}


def scaled(data: dict, factors: dict, cpu: bool = True) -> dict:
    """The fixture with each repetition's time of benchmark b multiplied by factors[b]
    (a number, or a list with one factor per repetition); rates divided alike;
    cpu=False leaves the CPU time as it was (foreign load: waiting, not working)."""
    out = copy.deepcopy(data)
    for e in out["benchmarks"]:
        f = factors.get(e["run_name"])
        if f is None or e["run_type"] != "iteration":
            continue
        k = f[e["repetition_index"]] if isinstance(f, list) else f
        e["real_time"] *= k
        if cpu:
            e["cpu_time"] *= k
        for name in list(e):
            if trend.is_rate_counter(name):
                e[name] /= k
    return out


def records(data: dict, run_id: str, **prov) -> list[dict]:
    return trend.make_records(trend.summarize(data), {**PROV, "run_id": run_id, **prov}, "bench_fixture")


class Summarize(unittest.TestCase):
    def setUp(self):
        self.data = trend.load_benchmark_json(FIXTURE)

    def test_MedianOfRepetitions_InSecondsWithMinMaxAndSpread(self):
        s = {x["benchmark"]: x for x in trend.summarize(self.data)}
        self.assertEqual(sorted(s), ["BM_axpy/1000", "BM_axpy/100000", "BM_sqrt"])
        for name, summ in s.items():
            reps = [e for e in self.data["benchmarks"] if e["run_name"] == name and e["run_type"] == "iteration"]
            times = [e["real_time"] * 1e-9 for e in reps]  # fixture time_unit is ns
            self.assertEqual(summ["repetitions"], 3)
            self.assertAlmostEqual(summ["real_time_s"]["median"], statistics.median(times), delta=1e-18)
            self.assertAlmostEqual(summ["real_time_s"]["min"], min(times), delta=1e-18)
            self.assertAlmostEqual(summ["spread"], (max(times) - min(times)) / statistics.median(times), places=12)
        axpy = s["BM_axpy/100000"]
        rates = [e["elements_per_s"] for e in self.data["benchmarks"]
                 if e["run_name"] == "BM_axpy/100000" and e["run_type"] == "iteration"]
        self.assertAlmostEqual(axpy["counters"]["elements_per_s"], statistics.median(rates), delta=1e-6)
        self.assertEqual(axpy["counters"]["bytes_per_element"], 16.0)
        self.assertEqual(s["BM_sqrt"]["counters"], {})

    def test_AggregatesOnlyOutput_FallsBackToMedianAggregate(self):
        data = copy.deepcopy(self.data)
        data["benchmarks"] = [e for e in data["benchmarks"] if e["run_type"] == "aggregate"]
        s = {x["benchmark"]: x for x in trend.summarize(data)}
        med = next(e for e in self.data["benchmarks"] if e["name"] == "BM_sqrt_median")
        self.assertAlmostEqual(s["BM_sqrt"]["real_time_s"]["median"], med["real_time"] * 1e-9, delta=1e-18)
        self.assertIsNone(s["BM_sqrt"]["spread"])

    def test_FailedBenchmark_IsAnErrorNamingIt(self):
        data = copy.deepcopy(self.data)
        data["benchmarks"][0]["error_occurred"] = True
        with self.assertRaisesRegex(trend.TrendError, "BM_axpy/1000 failed"):
            trend.summarize(data)


class History(unittest.TestCase):
    def test_Append_AddsOneLinePerRecordAndKeepsEarlierLines(self):
        data = trend.load_benchmark_json(FIXTURE)
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "sub" / "history.jsonl"
            self.assertEqual(trend.append_history(path, records(data, "r1")), 3)
            first = path.read_text()
            self.assertEqual(trend.append_history(path, records(data, "r2", commit="bbbbbbb")), 3)
            text = path.read_text()
            self.assertTrue(text.startswith(first))
            self.assertEqual(len(text.splitlines()), 6)
            hist = trend.load_history(path)
            self.assertEqual([r["run_id"] for r in hist], ["r1"] * 3 + ["r2"] * 3)
            for key in ("commit", "date", "compiler", "build_type", "host", "nproc", "cpu_model"):
                self.assertIn(key, hist[0])
            self.assertEqual(trend.last_run(hist)[0]["commit"], "bbbbbbb")

    def test_MalformedLine_IsAnErrorNamingFileAndLine(self):
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "history.jsonl"
            trend.append_history(path, records(trend.load_benchmark_json(FIXTURE), "r1"))
            with open(path, "a") as f:
                f.write("{not json\n")
            with self.assertRaisesRegex(trend.TrendError, r"history.jsonl:4:"):
                trend.load_history(path)


def without_memory_counter(data: dict) -> dict:
    out = copy.deepcopy(data)
    for e in out["benchmarks"]:
        e.pop("bytes_per_element", None)
    return out


class Regression(unittest.TestCase):
    def setUp(self):
        # Timing verdicts: drop the fixture's memory counter, which would be judged instead.
        self.data = without_memory_counter(trend.load_benchmark_json(FIXTURE))
        # Make the baseline's repeats nearly equal (spread 2 %) so the floor sets the band.
        flat = {}
        for name in ("BM_axpy/1000", "BM_axpy/100000", "BM_sqrt"):
            reps = [e["real_time"] for e in self.data["benchmarks"]
                    if e["run_name"] == name and e["run_type"] == "iteration"]
            med = statistics.median(reps)
            flat[name] = [med * (1 + d) / t for t, d in zip(reps, (-0.01, 0.0, 0.01))]
        self.base = scaled(self.data, flat)
        self.history = records(self.base, "r1")

    def verdicts(self, factors, floor=0.10, **prov):
        new = records(scaled(self.base, factors), "r2", commit="bbbbbbb", **prov)
        return {v["benchmark"]: v for v in trend.compare(self.history, new, floor)}

    def test_SlowdownBeyondFloor_IsRegression_WithinFloor_IsNoise(self):
        v = self.verdicts({"BM_axpy/1000": 1.25, "BM_axpy/100000": 1.05, "BM_sqrt": 0.7})
        self.assertEqual(v["BM_axpy/1000"]["status"], "regression")
        self.assertAlmostEqual(v["BM_axpy/1000"]["ratio"], 1.25, places=9)
        self.assertAlmostEqual(v["BM_axpy/1000"]["band"], 0.10, places=12)  # spreads 2 % < floor
        self.assertEqual(v["BM_axpy/100000"]["status"], "within noise")
        self.assertEqual(v["BM_sqrt"]["status"], "improvement")
        self.assertEqual(v["BM_sqrt"]["previous_commit"], "aaaaaaa")

    def test_MeasuredSpreadWiderThanFloor_WidensTheBand(self):
        # New repeats 1.0x, 1.3x, 1.6x of the baseline's (0.99, 1, 1.01) x median:
        # median ratio 1.3, spread (1.6 * 1.01 - 0.99) / 1.3 = 48 %.
        v = self.verdicts({"BM_axpy/1000": [1.0, 1.3, 1.6]})["BM_axpy/1000"]
        self.assertAlmostEqual(v["ratio"], 1.3, places=9)
        self.assertAlmostEqual(v["band"], (1.6 * 1.01 - 0.99) / 1.3, places=9)
        self.assertEqual(v["status"], "within noise")
        # The same median shift with tight repeats is a regression.
        self.assertEqual(self.verdicts({"BM_axpy/1000": 1.3})["BM_axpy/1000"]["status"], "regression")

    def test_MemoryCounter_IsJudgedOnBytesWithTheMemoryBand(self):
        base = trend.load_benchmark_json(FIXTURE)  # BM_axpy reports bytes_per_element = 16
        grown = copy.deepcopy(base)
        for e in grown["benchmarks"]:
            if e["run_name"] == "BM_axpy/1000" and "bytes_per_element" in e:
                e["bytes_per_element"] = 16.0 * 1.05
        history = records(base, "r1")
        new = records(scaled(grown, {"BM_axpy/100000": 3.0}), "r2")
        v = {x["benchmark"]: x for x in trend.compare(history, new)}
        self.assertEqual(v["BM_axpy/1000"]["metric"], "bytes_per_element")
        self.assertAlmostEqual(v["BM_axpy/1000"]["band"], trend.MEMORY_BAND)
        self.assertEqual(v["BM_axpy/1000"]["status"], "regression")  # 5 % more memory > 2 %
        self.assertEqual(v["BM_axpy/100000"]["status"], "within noise")  # 3x slower, same memory
        self.assertEqual(v["BM_sqrt"]["metric"], "real_time_s")

    def test_CpuTimeMetric_IgnoresWaitingUnderForeignLoad(self):
        new = records(scaled(self.base, {"BM_sqrt": 2.0}, cpu=False), "r2")
        real = {v["benchmark"]: v for v in trend.compare(self.history, new)}
        cpu = {v["benchmark"]: v for v in trend.compare(self.history, new, time_kind="cpu")}
        self.assertEqual(real["BM_sqrt"]["status"], "regression")
        self.assertEqual(cpu["BM_sqrt"]["metric"], "cpu_time_s")
        self.assertEqual(cpu["BM_sqrt"]["status"], "within noise")
        slower = records(scaled(self.base, {"BM_sqrt": 2.0}), "r3")
        self.assertEqual(trend.compare(self.history, slower, time_kind="cpu")[2]["status"], "regression")

    def test_SlowdownOnOversubscribedMachine_IsSuspectNotRegression(self):
        new = records(scaled(self.base, {"BM_sqrt": 2.0}), "r2")
        for rec in new:
            rec["load_avg"] = [8.0, 6.0, 4.0]  # 2 cores
        v = {x["benchmark"]: x for x in trend.compare(self.history, new)}
        self.assertEqual(v["BM_sqrt"]["status"], "suspect (loaded)")
        for rec in new:
            rec["load_avg"] = [1.5, 1.0, 1.0]
        v = {x["benchmark"]: x for x in trend.compare(self.history, new)}
        self.assertEqual(v["BM_sqrt"]["status"], "regression")

    def test_OtherMachineOrBuildType_IsNotCompared(self):
        self.assertEqual(self.verdicts({"BM_sqrt": 2.0}, host="other")["BM_sqrt"]["status"], "new")
        self.assertEqual(self.verdicts({"BM_sqrt": 2.0}, build_type="Debug")["BM_sqrt"]["status"], "new")

    def test_ComparesWithTheLatestEarlierRun(self):
        self.history += records(scaled(self.base, {"BM_sqrt": 2.0}), "r1b", commit="ccccccc")
        v = self.verdicts({"BM_sqrt": 2.0})["BM_sqrt"]
        self.assertEqual(v["previous_commit"], "ccccccc")
        self.assertEqual(v["status"], "within noise")


class ReportCsv(unittest.TestCase):
    def test_HistoryCsv_HasTheReportColumns_AndMarksTheRegression(self):
        base = trend.load_benchmark_json(FIXTURE)
        hist = records(base, "r1") + records(scaled(base, {"BM_sqrt": 3.0}), "r2", commit="bbbbbbb")
        rows = trend.history_csv_rows(hist)
        self.assertEqual(len(rows), 6)
        self.assertEqual(tuple(rows[0]), trend.HISTORY_CSV_COLUMNS)
        by = {(r["commit"], r["benchmark"]): r for r in rows}
        self.assertEqual(by[("bbbbbbb", "fixture:sqrt")]["regression"], 1)
        self.assertEqual(by[("bbbbbbb", "fixture:axpy/1000")]["regression"], 0)
        self.assertEqual(by[("aaaaaaa", "fixture:axpy/1000")]["unit"], "elements/s")
        self.assertEqual(by[("aaaaaaa", "fixture:sqrt")]["unit"], "s")
        self.assertEqual(trend.display_name({"executable": "bench_effects",
                                             "benchmark": "BM_Memory/tangential:0/iterations:1/real_time"}),
                         "effects:Memory/tangential:0")
        # A second run of the same commit replaces the first; another machine is left out.
        hist += records(base, "r4", commit="ccccccc", host="other") + records(base, "r3", commit="bbbbbbb")
        rows2 = trend.history_csv_rows(hist)
        self.assertEqual(len(rows2), 6)
        self.assertEqual([r["commit"] for r in rows2], ["aaaaaaa"] * 3 + ["bbbbbbb"] * 3)
        # The report's own strict reader accepts the file (reports/fdem_report/formats.py HISTORY).
        sys.path.insert(0, str(HERE.parents[1] / "reports"))
        try:
            from fdem_report import csvio, formats
        except ImportError as e:  # the report package is part of this tree; its absence is a failure
            self.fail(f"reports/fdem_report not importable: {e}")
        with tempfile.TemporaryDirectory() as tmp:
            path = Path(tmp) / "history.csv"
            with open(path, "w", newline="") as f:
                w = __import__("csv").DictWriter(f, fieldnames=trend.HISTORY_CSV_COLUMNS)
                w.writeheader()
                w.writerows(rows)
            table = csvio.read_table(path, formats.HISTORY)
            self.assertEqual(len(table.rows), 6)


class Command(unittest.TestCase):
    def run_cmd(self, tmp, *args):
        return subprocess.run([sys.executable, str(HERE / "run_trend.py"), "--history", str(tmp / "h.jsonl"),
                               "--build-dir", str(tmp), "--out", str(tmp / "out"), *args],
                              capture_output=True, text=True)

    def test_IngestTwice_FlagsRegressionWithExitStatus1_AndPlots(self):
        with tempfile.TemporaryDirectory() as t:
            tmp = Path(t)
            r = self.run_cmd(tmp, "--no-plot", "ingest", str(FIXTURE), "--executable", "bench_fixture")
            self.assertEqual(r.returncode, 0, r.stderr)
            slow = tmp / "slow.json"
            slow.write_text(json.dumps(scaled(trend.load_benchmark_json(FIXTURE), {"BM_sqrt": 3.0})))
            r = self.run_cmd(tmp, "ingest", str(slow), "--executable", "bench_fixture")
            self.assertEqual(r.returncode, 1, r.stdout + r.stderr)
            self.assertIn("REGRESSION", r.stdout)
            self.assertEqual(len((tmp / "h.jsonl").read_text().splitlines()), 6)
            with open(tmp / "out" / "trend_verdicts.csv") as f:
                rows = {row["benchmark"]: row["status"] for row in __import__("csv").DictReader(f)}
            self.assertEqual(rows["BM_sqrt"], "regression")
            # Both ingests carry this checkout's commit: one row per benchmark per commit, the latest.
            self.assertEqual(len((tmp / "results" / "benchmarks" / "history.csv").read_text().splitlines()), 4)
            pngs = sorted((tmp / "out").glob("trend_*.png"))
            self.assertEqual(len(pngs), 3)
            for png in pngs:
                self.assertEqual(png.read_bytes()[:8], b"\x89PNG\r\n\x1a\n")
            r = self.run_cmd(tmp, "--no-plot", "check")
            self.assertEqual(r.returncode, 1)

    def test_MalformedJson_ExitStatus2_NamesTheFile(self):
        with tempfile.TemporaryDirectory() as t:
            tmp = Path(t)
            bad = tmp / "bad.json"
            bad.write_text('{"benchmarks": [')
            r = self.run_cmd(tmp, "ingest", str(bad), "--executable", "x")
            self.assertEqual(r.returncode, 2)
            self.assertIn("bad.json", r.stderr)


if __name__ == "__main__":
    unittest.main(verbosity=2)
