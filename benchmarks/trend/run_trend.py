#!/usr/bin/python3
"""fdem benchmark trends: run the benchmark set, append to the history, flag
regressions beyond the noise band, plot each figure against commit.

  run_trend.py run    [--build-dir build] [--repetitions 5] [--min-time 0.2] [--filter RE]
                      [--executables bench_dem bench_fluid ...] [--no-append] [--no-fail]
  run_trend.py ingest FILE.json... --executable NAME [--build-dir build]   (results run elsewhere)
  run_trend.py check  (last run in the history against the run before it)
  run_trend.py plot   [--out DIR]

Files: the history (default benchmarks/history/history.jsonl, committed); its
flat copy for the report, <build>/results/benchmarks/history.csv (columns of
reports/FORMATS.md: commit,date,benchmark,value,unit,compiler,machine,
regression,noise_band_rel); and in --out (default <build>/results/benchmarks/trend/):
trend_*.png (one per benchmark), trend_index.csv (figure, latest value, png per
benchmark) and trend_verdicts.csv (the last comparison). Exit status 1 when a regression is
flagged (unless --no-fail), 2 on malformed input. See trend.py for the band.
"""
from __future__ import annotations

import argparse
import csv
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import trend  # noqa: E402

SOURCE_DIR = Path(__file__).resolve().parents[2]
DEFAULT_HISTORY = SOURCE_DIR / "benchmarks" / "history" / "history.jsonl"


def find_executables(build_dir: Path, names: list[str] | None) -> list[Path]:
    found = sorted(p for p in (build_dir / "benchmarks").rglob("bench_*")
                   if p.is_file() and os.access(p, os.X_OK))
    if names:
        by_name = {p.name: p for p in found}
        missing = [n for n in names if n not in by_name]
        if missing:
            raise trend.TrendError(f"not built in {build_dir}: {', '.join(missing)}")
        return [by_name[n] for n in names]
    return found


def run_one(exe: Path, repetitions: int, min_time: float, flt: str | None, interleave: bool = False) -> dict:
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "out.json"
        cmd = [str(exe), f"--benchmark_repetitions={repetitions}", f"--benchmark_min_time={min_time}",
               f"--benchmark_out={out}", "--benchmark_out_format=json"]
        if flt:
            cmd.append(f"--benchmark_filter={flt}")
        if interleave:
            cmd.append("--benchmark_enable_random_interleaving=true")
        print("+", " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True)
        return trend.load_benchmark_json(out)


def write_csv(path: Path, rows: list[dict]) -> None:
    if not rows:
        return
    path.parent.mkdir(parents=True, exist_ok=True)
    with open(path, "w", newline="", encoding="utf-8") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
        w.writeheader()
        w.writerows(rows)


def finish(args, history: list[dict], new_records: list[dict], recorded: bool = False) -> int:
    verdicts = trend.compare(history, new_records, args.noise_floor, args.time)
    print(trend.format_verdicts(verdicts))
    out = Path(args.out)
    write_csv(out / "trend_verdicts.csv", verdicts)
    if not args.no_append and new_records:
        n = trend.append_history(args.history, new_records)
        print(f"appended {n} records to {args.history}")
    full_history = history if recorded else (trend.load_history(args.history) if not args.no_append
                                             else history + new_records)
    write_csv(Path(args.history_csv), trend.history_csv_rows(full_history, args.noise_floor, args.time))
    if not args.no_plot:
        index = trend.plot_history(full_history, out, floor=args.noise_floor, time_kind=args.time)
        write_csv(out / "trend_index.csv", index)
        print(f"wrote {len(index)} plots to {out}")
    suspects = [v for v in verdicts if v["status"].startswith("suspect")]
    if suspects:
        print(f"{len(suspects)} slowdown(s) beyond the noise band on an oversubscribed machine "
              "(load average > cores): suspect, rerun on a quiet machine", file=sys.stderr)
    regressions = [v for v in verdicts if v["status"] == "regression"]
    if regressions:
        print(f"{len(regressions)} REGRESSION(S) beyond the noise band", file=sys.stderr)
        return 0 if args.no_fail else 1
    return 0


def cmd_run(args) -> int:
    if args.omp_threads is not None:
        os.environ["OMP_NUM_THREADS"] = str(args.omp_threads)
    build = Path(args.build_dir)
    history = trend.load_history(args.history)
    prov = trend.provenance(SOURCE_DIR, build)
    records = []
    for exe in find_executables(build, args.executables):
        data = run_one(exe, args.repetitions, args.min_time, args.filter, args.interleave)
        summaries = trend.summarize(data, str(exe))
        records += trend.make_records(summaries, prov, exe.name, data.get("context", {}).get("load_avg"))
    if not records:
        raise trend.TrendError(f"no benchmark executable (bench_*) under {build / 'benchmarks'}")
    return finish(args, history, records)


def cmd_ingest(args) -> int:
    history = trend.load_history(args.history)
    prov = trend.provenance(SOURCE_DIR, Path(args.build_dir))
    records = []
    for path in args.files:
        data = trend.load_benchmark_json(path)
        records += trend.make_records(trend.summarize(data, path), prov, args.executable,
                                      data.get("context", {}).get("load_avg"))
    return finish(args, history, records)


def cmd_check(args) -> int:
    history = trend.load_history(args.history)
    args.no_append = True  # compare() skips the new run's own records
    return finish(args, history, trend.last_run(history), recorded=True)


def cmd_plot(args) -> int:
    history = trend.load_history(args.history)
    write_csv(Path(args.history_csv), trend.history_csv_rows(history, args.noise_floor, args.time))
    index = trend.plot_history(history, args.out, floor=args.noise_floor, time_kind=args.time)
    write_csv(Path(args.out) / "trend_index.csv", index)
    print(f"wrote {len(index)} plots to {args.out}")
    return 0


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--history", default=str(DEFAULT_HISTORY), help="JSON Lines history file")
    p.add_argument("--build-dir", default=str(SOURCE_DIR / "build"))
    p.add_argument("--out", default=None, help="plots and CSVs (default <build>/results/benchmarks/trend)")
    p.add_argument("--history-csv", default=None,
                   help="the history as the report reads it (default <build>/results/benchmarks/history.csv)")
    p.add_argument("--noise-floor", type=float, default=trend.DEFAULT_NOISE_FLOOR,
                   help="smallest relative band a slowdown must exceed (default %(default)s)")
    p.add_argument("--time", choices=("real", "cpu"), default="real",
                   help="judge regressions on real time (default) or on the main thread's CPU time, "
                        "steadier under foreign load for single-threaded runs (OMP_NUM_THREADS=1)")
    p.add_argument("--no-plot", action="store_true")
    p.add_argument("--no-append", action="store_true", help="compare only; leave the history alone")
    p.add_argument("--no-fail", action="store_true", help="exit 0 even when a regression is flagged")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser("run", help="run the benchmark executables and record them")
    r.add_argument("--executables", nargs="*", help="names (default: every bench_* built)")
    r.add_argument("--repetitions", type=int, default=5)
    r.add_argument("--min-time", type=float, default=0.2, help="seconds per repetition")
    r.add_argument("--filter", default=None, help="--benchmark_filter regex")
    r.add_argument("--interleave", action="store_true",
                   help="run the repetitions of all benchmarks in random order (spreads load drift evenly)")
    r.add_argument("--omp-threads", type=int, default=None,
                   help="OMP_NUM_THREADS for the runs (benchmarks that set their own thread count keep it)")
    i = sub.add_parser("ingest", help="record Google Benchmark JSON files run elsewhere")
    i.add_argument("files", nargs="+")
    i.add_argument("--executable", required=True, help="the name the records carry")
    sub.add_parser("check", help="compare the history's last run with the one before")
    sub.add_parser("plot", help="plot the history")
    args = p.parse_args(argv)
    if args.out is None:
        args.out = str(Path(args.build_dir) / "results" / "benchmarks" / "trend")
    if args.history_csv is None:
        args.history_csv = str(Path(args.build_dir) / "results" / "benchmarks" / "history.csv")
    try:
        return {"run": cmd_run, "ingest": cmd_ingest, "check": cmd_check, "plot": cmd_plot}[args.command](args)
    except trend.TrendError as e:
        print(f"run_trend: {e}", file=sys.stderr)
        return 2
    except subprocess.CalledProcessError as e:
        print(f"run_trend: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
