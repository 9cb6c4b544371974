#!/usr/bin/python3
"""Write the fdem validation report (reports/out/index.html and report.pdf).

    /usr/bin/python3 reports/generate.py --results build/results \
        --build-info build/build_info.json --out reports/out

Reads reference_data/*.csv (next to this script's parent folder unless
--reference-dir is given) and the files each study writes under --results, as
specified in reports/FORMATS.md. Exit codes: 0 written; 2 a malformed input
file (the message names the file and line); 1 with --strict when any row FAILs.
"""
from __future__ import annotations

import argparse
import csv
import os
import sys
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from fdem_report import formats, inputs, plugins, provenance, summary, verdicts  # noqa: E402
from fdem_report.csvio import InputError  # noqa: E402


@dataclass
class StudySection:
    name: str
    title: str
    folder: Path
    results: inputs.StudyResults | None
    rows: list = field(default_factory=list)
    plots: list = field(default_factory=list)
    stale: str = ""  # why the results are not this commit's ("" when they are)

    @property
    def run_provenance(self) -> str:
        return provenance.run_summary(self.results.meta if self.results else None)

    @property
    def sentences(self) -> list[str]:
        return verdicts.study_verdict(self)

    @property
    def tier(self) -> str:
        return str(self.results.meta["tier"]) if self.results and self.results.meta else "-"

    @property
    def wall_time(self) -> str:
        return f"{self.results.meta['wall_time_s']:.4g}" if self.results and self.results.meta else "-"

    @property
    def verdict(self) -> str:
        r = self.results
        if not r or (r.meta is None and r.values is None and not r.series):
            return "not run"
        if r.meta is None:
            return "no meta.json"
        if self.stale:
            return "stale"
        return "passed" if r.meta["passed"] else "failed"

    @property
    def counts(self) -> dict:
        return summary.counts(self.rows)

    @property
    def unreferenced(self) -> list[tuple[str, float]]:
        if not self.results or not self.results.values:
            return []
        known = {r.ref.id for r in self.rows}
        known |= {f"{k}.{u}" for k in known for u in ("u_num", "u_input")}  # shown beside their row
        return [(k, v) for k, v in self.results.values.items() if k not in known]

    @property
    def unread(self) -> list[str]:
        return self.results.unread if self.results else []


@dataclass
class Report:
    rows: list
    studies: list[StudySection]
    provenance: list[tuple[str, str]]
    headline: str
    expected_commit: str | None = None
    legend: str = ("Rows are classed (reference_data/README.md): verification (the solver against an exact or "
                   "independent solution of the same equations), validation (against an experiment), reproduction "
                   "(against the paper's numbers), consistency (input echo, closed-form arithmetic: no solver ran). "
                   "Only the first three are judged. PASS: |ours - reference| within the tolerance (rel: a fraction "
                   "of the reference; abs: in the row's unit; pp: percentage points; >= / <=: one-sided). FAIL: "
                   "outside it, or our value is not finite. CONSISTENT / MISMATCH: the same test on a consistency "
                   "row, never counted as a pass. STALE: the study ran on another commit or an older scene: shown, "
                   "not judged. NOT RUN: the study did not run or did not measure this row (never a pass). INFO: no "
                   "tolerance, tabulated only. Deviation = ours - reference; dev. % relative to |reference|. "
                   "'run' = the tier that produced the value and when it finished (UTC).")

    @property
    def counts(self) -> dict:
        return summary.counts(self.rows)

    @property
    def vv20(self) -> list[dict]:
        return verdicts.vv20_rows(self.rows)


def parse_args(argv):
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--results", type=Path, required=True, help="folder with one sub-folder per study")
    p.add_argument("--build-info", type=Path, help="build/build_info.json (commit, build type, compiler)")
    p.add_argument("--out", type=Path, required=True, help="output folder (index.html, report.pdf, summary.csv)")
    p.add_argument("--reference-dir", type=Path, default=HERE.parent / "reference_data")
    p.add_argument("--history", type=Path, help="benchmark history CSV (default: <results>/benchmarks/history.csv)")
    p.add_argument("--strict", action="store_true", help="exit 1 when any row is FAIL")
    p.add_argument("--no-pdf", action="store_true", help="skip report.pdf (faster)")
    p.add_argument("--expect-commit", help="commit the results must come from (default: HEAD of the source tree); "
                   "results of any other commit are marked STALE")
    p.add_argument("--source-dir", type=Path, default=HERE.parent,
                   help="source tree whose HEAD and scene files the runs are checked against")
    return p.parse_args(argv)


def load(args) -> Report:
    """Read and check every input; no drawing yet."""
    if not args.reference_dir.is_dir():
        raise InputError(args.reference_dir, None, "reference data folder not found")
    if args.history is not None and not args.history.is_file():
        raise InputError(args.history, None, "benchmark history file not found")
    plugins.register(args.source_dir)  # verification/<study>/report_figures.py: a study's own plots and files
    refs = inputs.load_references(args.reference_dir)
    results = inputs.load_results(args.results, args.history)
    # A study's own checks of its inputs (e.g. the plume's full grids) before anything is drawn.
    for study, check in plugins.CHECKS.items():
        if results.get(study):
            check(results[study])
    from fdem_report.figures import PLOTTERS as figures_for
    # Every study with plots is shown even when it did not run (its notes say so).
    order = formats.ORDER + [s for s in {**formats.STUDIES, **figures_for} if s not in formats.ORDER]
    names = [s for s in order if s in refs or s in results or s in figures_for]
    names += sorted((set(refs) | set(results)) - set(names))
    expected = args.expect_commit or provenance.source_commit(args.source_dir)
    stale = {n: provenance.staleness(results[n].meta, expected, args.source_dir) for n in results}
    rows = summary.build_rows({n: refs[n] for n in names if n in refs}, results, stale)
    studies = [StudySection(n, formats.STUDIES.get(n, n.replace("_", " ").capitalize()), args.results / n,
                            results.get(n), [r for r in rows if r.ref.study == n], stale=stale.get(n, ""))
               for n in names]
    prov = provenance.collect(args.build_info)
    prov.insert(0, ("results", str(args.results.resolve())))
    prov.insert(1, ("results expected from commit", expected or "unknown (no git checkout: staleness not checked)"))
    steps = args.results / "nightly_steps.csv"  # scripts/nightly.sh: each step's wall time and the load
    if steps.is_file():
        for line in steps.read_text(encoding="utf-8").splitlines()[1:]:
            f = line.split(",")
            if len(f) == 5:
                prov.append((f"nightly step {f[0]}", f"{f[1]} s wall, exit {f[2]}, load {f[3]} at its end, {f[4]}"))
    load_log = args.results / "nightly_load.csv"  # scripts/nightly.sh: the 1-minute load average every minute
    if load_log.is_file():
        loads = sorted(float(f[1]) for f in (line.split(",") for line in load_log.read_text(encoding="utf-8").splitlines()[1:])
                       if len(f) == 4)
        if loads:
            prov.append(("nightly load (1-min average, sampled each minute)",
                         f"min {loads[0]:g}, median {loads[len(loads) // 2]:g}, max {loads[-1]:g} over {len(loads)} "
                         f"samples on {os.cpu_count()} cores"))
    info = dict(prov)
    headline = (f"commit {info['commit']} · {info['build type']} · {info['compiler']} · {info['machine']} · "
                f"{info['report date (UTC)']} UTC · results {args.results}")
    return Report(rows, studies, prov, headline, expected_commit=expected)


def draw(report: Report) -> None:
    from fdem_report import figures
    from fdem_report.html_writer import png_base64
    for s in report.studies:
        plotter = figures.PLOTTERS.get(s.name)
        # A study without its own plots still gets its rows drawn against their tolerances.
        s.plots = plotter(s.results) if plotter else figures.rows_figure(s.name, s.rows)
        for p in s.plots:
            p.png = png_base64(p.fig) if p.fig is not None else ""


def write_summary_csv(path: Path, rows) -> None:
    """Machine-readable verdicts, so two reports can be diffed."""
    tmp = path.with_suffix(".csv.tmp")
    with tmp.open("w", newline="", encoding="utf-8") as f:
        w = csv.writer(f)
        w.writerow(["id", "study", "class", "status", "ours", "reference", "unit", "dev_abs", "dev_pct", "tolerance",
                    "tolerance_kind", "gate", "u_num", "u_input", "u_ref", "tier", "finished_utc", "note"])
        for r in rows:
            w.writerow([r.ref.id, r.ref.study, r.ref.row_class, r.status, "" if r.ours is None else repr(r.ours),
                        repr(r.ref.value), r.ref.unit, summary.fmt(r.dev_abs, 6), summary.fmt(r.dev_pct, 6),
                        "" if r.ref.tolerance is None else repr(r.ref.tolerance), r.ref.tolerance_kind,
                        "yes" if r.ref.gate else "no", summary.fmt(r.u_num, 6), summary.fmt(r.u_input, 6),
                        summary.fmt(r.ref.u_ref, 6), r.tier, r.when, r.note])
    os.replace(tmp, path)


def main(argv=None) -> int:
    args = parse_args(argv)
    import matplotlib
    matplotlib.use("Agg")  # files only, never a display
    try:
        report = load(args)
    except InputError as e:
        print(f"generate.py: error: {e}", file=sys.stderr)
        return 2
    from fdem_report import html_writer, pdf_writer
    draw(report)
    args.out.mkdir(parents=True, exist_ok=True)
    # Write to temporary names, then rename: a crash never leaves half a report.
    html_writer.write(args.out / "index.html.tmp", report)
    os.replace(args.out / "index.html.tmp", args.out / "index.html")
    if not args.no_pdf:
        pdf_writer.write(args.out / "report.pdf.tmp", report)
        os.replace(args.out / "report.pdf.tmp", args.out / "report.pdf")
    write_summary_csv(args.out / "summary.csv", report.rows)
    c = report.counts
    print(f"fdem report: {c['FAIL']} FAIL, {c['PASS']} PASS, {c['NOT RUN']} NOT RUN, {c['INFO']} INFO, "
          f"{c['STALE']} STALE, {c['CONSISTENT']} CONSISTENT, {c['MISMATCH']} MISMATCH "
          f"-> {args.out / 'index.html'}" + ("" if args.no_pdf else f", {args.out / 'report.pdf'}"))
    return 1 if args.strict and (c["FAIL"] or c["MISMATCH"]) else 0


if __name__ == "__main__":
    sys.exit(main())
