"""Benchmark trends: Google Benchmark JSON -> history records -> regression flags -> plots.

Library half of run_trend.py (the command). Only the Python standard library is
needed for everything except plot_history(), which imports matplotlib lazily, so
the regression logic and the history append run (and are unit tested) anywhere.

One history record = one benchmark of one executable in one trend run:
    {"schema": 1, "run_id", "date", "commit", "dirty", "compiler", "build_type",
     "host", "nproc", "cpu_model", "executable", "benchmark", "repetitions",
     "threads", "real_time_s": {"median", "min", "max"}, "cpu_time_s_median",
     "spread", "counters": {name: median}, "load_avg"}
The history file is JSON Lines (one record a line) so an append never rewrites
what is there and a merge conflict stays one line wide.

Noise band (why a regression needs more than "slower than last time"):
a figure is the MEDIAN of N repetitions; its repeat spread is
(max - min) / median over those repetitions. The machine is shared: LIGGGHTS
on it showed 8-9 % spread on a contact-bound scene and 18-30 % on a
memory-bound one with no other process running (shared/anchors/liggghts/results.md),
and our own repeats are recorded in every record. A benchmark is flagged as a
regression only when
    new_median > previous_median * (1 + band),
    band = max(noise_floor, spread_previous, spread_new),
i.e. the slowdown must exceed both a floor (default 10 %, the quiet-machine
spread of the contact-bound scene) and the spread actually measured in either
run: a shift smaller than the range of the repeats themselves cannot be told
from the machine's noise. benchmarks/README.md gives the spreads measured on
this machine. When either run started on an oversubscribed machine (load
average above the core count) a slowdown beyond the band is reported as
'suspect (loaded)', not as a regression: between runs under such load even
unchanged code moved by more than its repeat spread. A benchmark that reports a memory counter (bytes...) is judged on
it instead, with a fixed 2 % band: memory of a fixed scene does not depend on load.
"""
from __future__ import annotations

import datetime as _dt
import json
import math
import os
import re
import socket
import statistics
import subprocess
import uuid
from pathlib import Path
from typing import Iterable

SCHEMA = 1
DEFAULT_NOISE_FLOOR = 0.10

_TIME_UNIT_S = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}
# Keys Google Benchmark writes itself; every other numeric key is a user counter.
_STANDARD_KEYS = {
    "name", "family_index", "per_family_instance_index", "run_name", "run_type",
    "repetitions", "repetition_index", "threads", "iterations", "real_time",
    "cpu_time", "time_unit", "aggregate_name", "aggregate_unit", "error_occurred",
    "error_message", "label", "big_o", "rms",
}
# Counter names that are throughputs (higher is better); the first one found is
# the figure a benchmark's trend plot shows.
_RATE_SUFFIXES = ("per_s", "per_second", "/s")


class TrendError(Exception):
    """A malformed input: the message names the file (and line) at fault."""


# Memory is deterministic for a fixed scene up to allocator rounding: a growth
# beyond 2 % is real, whatever the timing noise.
MEMORY_BAND = 0.02


def is_rate_counter(name: str) -> bool:
    return name.endswith(_RATE_SUFFIXES)


def is_memory_counter(name: str) -> bool:
    return name.startswith("bytes")


def regression_metric(rec: dict, time_kind: str = "real") -> tuple[str, float]:
    """What a regression is judged on (lower is better for all): a memory
    counter (bytes...) where the benchmark reports one, else the median real
    time, or with time_kind 'cpu' the median CPU time of the benchmark's main
    thread (load on a shared machine inflates real time, not CPU time; only
    meaningful for single-threaded runs)."""
    memory = sorted(k for k in rec.get("counters", {}) if is_memory_counter(k))
    if memory:
        return memory[0], rec["counters"][memory[0]]
    if time_kind == "cpu" and "cpu_time_s" in rec:
        return "cpu_time_s", rec["cpu_time_s"]["median"]
    return "real_time_s", rec["real_time_s"]["median"]


# --------------------------------------------------------------------------
# 1. Google Benchmark JSON -> one summary per benchmark (median of repeats)
# --------------------------------------------------------------------------
def load_benchmark_json(path: str | os.PathLike) -> dict:
    try:
        with open(path, encoding="utf-8") as f:
            data = json.load(f)
    except json.JSONDecodeError as e:
        raise TrendError(f"{path}:{e.lineno}: not valid JSON ({e.msg})") from e
    if not isinstance(data, dict) or not isinstance(data.get("benchmarks"), list):
        raise TrendError(f"{path}: no 'benchmarks' list: not Google Benchmark JSON")
    return data


def summarize(data: dict, source: str = "<json>") -> list[dict]:
    """Median, min, max of the repetitions of each benchmark in one JSON output.

    Uses the per-repetition ("iteration") entries; when a run kept only the
    aggregates (--benchmark_report_aggregates_only) it falls back to the
    "median" aggregate and the spread is unknown (None)."""
    iterations: dict[str, list[dict]] = {}
    medians: dict[str, dict] = {}
    order: list[str] = []
    for entry in data["benchmarks"]:
        run_name = entry.get("run_name", entry.get("name"))
        if run_name is None:
            raise TrendError(f"{source}: a benchmark entry has no name")
        if run_name not in order:
            order.append(run_name)
        if entry.get("error_occurred"):
            raise TrendError(f"{source}: benchmark {run_name} failed: {entry.get('error_message', '')}")
        if entry.get("run_type", "iteration") == "iteration":
            iterations.setdefault(run_name, []).append(entry)
        elif entry.get("aggregate_name") == "median":
            medians[run_name] = entry

    # Registration order (stable under --benchmark_enable_random_interleaving).
    position = {}
    for entry in data["benchmarks"]:
        name = entry.get("run_name", entry.get("name"))
        position.setdefault(name, (entry.get("family_index", 0), entry.get("per_family_instance_index", 0)))
    order.sort(key=lambda name: position[name])
    summaries = []
    for run_name in order:
        reps = iterations.get(run_name)
        if reps:
            unit = _TIME_UNIT_S[reps[0].get("time_unit", "ns")]
            real = [float(r["real_time"]) * unit for r in reps]
            cpu = [float(r["cpu_time"]) * unit for r in reps]
            counter_names = sorted({k for r in reps for k, v in r.items()
                                    if k not in _STANDARD_KEYS and isinstance(v, (int, float))})
            counters = {k: statistics.median(float(r[k]) for r in reps if k in r) for k in counter_names}
            med = statistics.median(real)
            cpu_med = statistics.median(cpu)
            summary = {
                "benchmark": run_name,
                "repetitions": len(reps),
                "threads": int(reps[0].get("threads", 1)),
                "real_time_s": {"median": med, "min": min(real), "max": max(real)},
                "cpu_time_s_median": cpu_med,
                "cpu_time_s": {"median": cpu_med, "min": min(cpu), "max": max(cpu)},
                "spread": (max(real) - min(real)) / med if med > 0 else None,
                "cpu_spread": (max(cpu) - min(cpu)) / cpu_med if cpu_med > 0 else None,
                "counters": counters,
            }
        elif run_name in medians:
            m = medians[run_name]
            unit = _TIME_UNIT_S[m.get("time_unit", "ns")]
            med = float(m["real_time"]) * unit
            summary = {
                "benchmark": run_name,
                "repetitions": int(m.get("repetitions", 1)),
                "threads": int(m.get("threads", 1)),
                "real_time_s": {"median": med, "min": None, "max": None},
                "cpu_time_s_median": float(m["cpu_time"]) * unit,
                "spread": None,
                "counters": {k: float(v) for k, v in m.items()
                             if k not in _STANDARD_KEYS and isinstance(v, (int, float))},
            }
        else:
            continue
        if not (summary["real_time_s"]["median"] > 0 and math.isfinite(summary["real_time_s"]["median"])):
            raise TrendError(f"{source}: benchmark {run_name} has real_time {summary['real_time_s']['median']}")
        summaries.append(summary)
    return summaries


# --------------------------------------------------------------------------
# 2. Provenance: commit, compiler, build type, machine
# --------------------------------------------------------------------------
def cpu_model() -> str:
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return "unknown"


def machine_info() -> dict:
    return {"host": socket.gethostname(), "nproc": os.cpu_count() or 1, "cpu_model": cpu_model()}


def git_info(source_dir: str | os.PathLike) -> dict:
    def git(*args: str) -> str | None:
        try:
            out = subprocess.run(["git", "-C", str(source_dir), *args], capture_output=True,
                                 text=True, check=True, timeout=30)
            return out.stdout.strip()
        except (OSError, subprocess.SubprocessError):
            return None
    commit = git("rev-parse", "--short", "HEAD")
    status = git("status", "--porcelain", "--untracked-files=no")
    return {"commit": commit or "unknown", "dirty": bool(status) if status is not None else None}


def build_info(build_dir: str | os.PathLike) -> dict:
    """compiler / build_type / commit that CMake wrote to build_info.json at configure time."""
    path = Path(build_dir) / "build_info.json"
    if not path.exists():
        return {}
    try:
        return json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as e:
        raise TrendError(f"{path}:{e.lineno}: not valid JSON ({e.msg})") from e


def provenance(source_dir, build_dir, run_id: str | None = None) -> dict:
    info = build_info(build_dir)
    git = git_info(source_dir)
    now = _dt.datetime.now(_dt.timezone.utc).replace(microsecond=0)
    return {
        "run_id": run_id or now.strftime("%Y%m%dT%H%M%SZ-") + uuid.uuid4().hex[:6],
        "date": now.isoformat().replace("+00:00", "Z"),
        "commit": git["commit"] if git["commit"] != "unknown" else info.get("commit", "unknown"),
        "dirty": git["dirty"],
        "compiler": info.get("compiler", "unknown"),
        "build_type": info.get("build_type", "unknown"),
        **machine_info(),
    }


def make_records(summaries: Iterable[dict], prov: dict, executable: str, load_avg=None) -> list[dict]:
    records = []
    for s in summaries:
        rec = {"schema": SCHEMA, **prov, "executable": executable, **s}
        if load_avg is not None:
            rec["load_avg"] = load_avg
        records.append(rec)
    return records


# --------------------------------------------------------------------------
# 3. History file (JSON Lines)
# --------------------------------------------------------------------------
_REQUIRED = ("run_id", "commit", "executable", "benchmark", "real_time_s", "host", "nproc", "build_type")


def load_history(path: str | os.PathLike) -> list[dict]:
    path = Path(path)
    if not path.exists():
        return []
    records = []
    with open(path, encoding="utf-8") as f:
        for lineno, line in enumerate(f, 1):
            if not line.strip():
                continue
            try:
                rec = json.loads(line)
            except json.JSONDecodeError as e:
                raise TrendError(f"{path}:{lineno}: not valid JSON ({e.msg})") from e
            missing = [k for k in _REQUIRED if k not in rec]
            if missing:
                raise TrendError(f"{path}:{lineno}: record lacks {', '.join(missing)}")
            records.append(rec)
    return records


def append_history(path: str | os.PathLike, records: Iterable[dict]) -> int:
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    n = 0
    with open(path, "a", encoding="utf-8") as f:
        for rec in records:
            f.write(json.dumps(rec, sort_keys=True, separators=(",", ":")) + "\n")
            n += 1
    return n


# --------------------------------------------------------------------------
# 4. Regression check: new median against the previous median, beyond noise
# --------------------------------------------------------------------------
def comparison_key(rec: dict) -> tuple:
    """Only runs on the same machine and build type are comparable."""
    return (rec["executable"], rec["benchmark"], rec["host"], rec["nproc"], rec["build_type"])


def loaded(rec: dict) -> bool:
    """The machine was oversubscribed when the run started: 1-minute load
    average (Google Benchmark's context) above the core count."""
    load = rec.get("load_avg")
    return bool(load) and float(load[0]) > float(rec.get("nproc", 1))


def noise_band(prev: dict, new: dict, floor: float = DEFAULT_NOISE_FLOOR, time_kind: str = "real") -> float:
    key = "cpu_spread" if time_kind == "cpu" else "spread"
    spreads = [s for s in (prev.get(key), new.get(key)) if s is not None]
    return max([floor, *spreads])


def compare(history: list[dict], new_records: list[dict], floor: float = DEFAULT_NOISE_FLOOR,
            time_kind: str = "real") -> list[dict]:
    """For each new record, the verdict against the latest earlier run with the same key.

    status: 'regression' (slower beyond the band), 'suspect (loaded)' (the same,
    but a run started on an oversubscribed machine), 'improvement' (faster
    beyond the band), 'within noise', or 'new' (nothing to compare with)."""
    latest: dict[tuple, dict] = {}
    new_run_ids = {r["run_id"] for r in new_records}
    for rec in history:  # file order = time order
        if rec["run_id"] not in new_run_ids:
            latest[comparison_key(rec)] = rec
    verdicts = []
    for rec in new_records:
        prev = latest.get(comparison_key(rec))
        metric, new_value = regression_metric(rec, time_kind)
        v = {"executable": rec["executable"], "benchmark": rec["benchmark"], "metric": metric,
             "new_value": new_value, "new_spread": rec.get("spread"), "previous_value": None,
             "previous_commit": None, "ratio": None, "band": None, "status": "new"}
        if prev is not None and regression_metric(prev, time_kind)[0] == metric:
            prev_value = regression_metric(prev, time_kind)[1]
            band = MEMORY_BAND if is_memory_counter(metric) else noise_band(prev, rec, floor, time_kind)
            ratio = new_value / prev_value
            if ratio > 1.0 + band:
                # On an oversubscribed machine a shift between runs exceeds the
                # repeat spread (measured here: unchanged kernels moved by a median
                # 18 %, up to 50 %, at load 9-13 on 2 cores): flag, do not fail.
                status = "suspect (loaded)" if loaded(prev) or loaded(rec) else "regression"
            elif ratio < 1.0 / (1.0 + band):
                status = "improvement"
            else:
                status = "within noise"
            v.update(previous_value=prev_value, previous_commit=prev["commit"], ratio=ratio,
                     band=band, status=status)
        verdicts.append(v)
    return verdicts


def last_run(history: list[dict]) -> list[dict]:
    if not history:
        return []
    run_id = history[-1]["run_id"]
    return [r for r in history if r["run_id"] == run_id]


def format_verdicts(verdicts: list[dict]) -> str:
    lines = [f"{'status':<17} {'ratio':>7} {'band':>6}  {'new':>11} {'previous':>11}  {'metric':<18} benchmark"]
    for v in verdicts:
        ratio = f"{v['ratio']:.3f}" if v["ratio"] is not None else "-"
        band = f"{100 * v['band']:.0f}%" if v["band"] is not None else "-"
        prev = f"{v['previous_value']:.4g}" if v["previous_value"] is not None else "-"
        flag = "REGRESSION" if v["status"] == "regression" else v["status"]
        lines.append(f"{flag:<17} {ratio:>7} {band:>6}  {v['new_value']:>11.4g} {prev:>11}  {v['metric']:<18} "
                     f"{v['executable']}:{v['benchmark']}")
    return "\n".join(lines)


def verdicts_along_history(history: list[dict], floor: float = DEFAULT_NOISE_FLOOR,
                           time_kind: str = "real") -> list[tuple[dict, dict]]:
    """(record, verdict against the run before it with the same key), run by run in file order."""
    out: list[tuple[dict, dict]] = []
    seen_runs: list[str] = []
    by_run: dict[str, list[dict]] = {}
    for rec in history:
        if rec["run_id"] not in by_run:
            seen_runs.append(rec["run_id"])
        by_run.setdefault(rec["run_id"], []).append(rec)
    done: list[dict] = []
    for run_id in seen_runs:
        out += list(zip(by_run[run_id], compare(done, by_run[run_id], floor, time_kind)))
        done += by_run[run_id]
    return out


def unit_of(figure: str) -> str:
    """'particle_steps_per_s' -> 'particle_steps/s'; 'real_time_s' -> 's'; 'bytes_per_particle' -> 'B/particle'."""
    if figure == "real_time_s":
        return "s"
    if figure.startswith("bytes_per_"):
        return "B/" + figure[len("bytes_per_"):]
    for suffix in _RATE_SUFFIXES:
        if figure.endswith(suffix):
            return figure[: -len(suffix)].rstrip("_") + "/s"
    return "-"


# Columns of $RESULTS/benchmarks/history.csv as the report reads it
# (reports/fdem_report/formats.py HISTORY; reports/FORMATS.md).
HISTORY_CSV_COLUMNS = ("commit", "date", "benchmark", "value", "unit", "compiler", "machine",
                       "regression", "noise_band_rel")


def display_name(rec: dict) -> str:
    """'bench_effects', 'BM_Effects_x/omp:1/real_time' -> 'effects:Effects_x/omp:1': the
    report prints it above a small plot, so drop what every name repeats."""
    name = re.sub(r"/(real_time|iterations:\d+|manual_time)(?=/|$)", "", rec["benchmark"])
    name = re.sub(r"^BM_", "", name)
    return f"{re.sub(r'^bench_', '', rec['executable'])}:{name}"


# The report draws the first 12 benchmarks of history.csv: headline scenes first.
_EXECUTABLE_ORDER = ("bench_scenes", "bench_dem", "bench_fluid", "bench_effects", "bench_coupling")


def history_csv_rows(history: list[dict], floor: float = DEFAULT_NOISE_FLOOR, time_kind: str = "real") -> list[dict]:
    """The history as reports/FORMATS.md wants it: one row per benchmark per
    commit (the latest run of that commit), oldest first, one machine (that of
    the latest record: figures from two machines do not belong on one line);
    value = the benchmark's figure (figure_of), regression = 1 where it was
    flagged against the run before it, noise_band_rel = the band used."""
    if not history:
        return []
    host = history[-1]["host"]
    run_order: dict[str, int] = {}
    latest: dict[tuple, tuple] = {}
    for index, (rec, v) in enumerate(verdicts_along_history(history, floor, time_kind)):
        if rec["host"] != host:
            continue
        run_order.setdefault(rec["run_id"], len(run_order))
        commit = rec["commit"] + ("+" if rec.get("dirty") else "")
        latest[(commit, rec["executable"], rec["benchmark"])] = (rec, v, index)

    def order(item):
        rec, _, index = item
        exe = rec["executable"]
        rank = _EXECUTABLE_ORDER.index(exe) if exe in _EXECUTABLE_ORDER else len(_EXECUTABLE_ORDER)
        return (run_order[rec["run_id"]], rank, index)

    rows = []
    for rec, v, _ in sorted(latest.values(), key=order):
        name, value, _, _ = figure_of(rec)
        rows.append({
            "commit": rec["commit"] + ("+" if rec.get("dirty") else ""),
            "date": rec.get("date", ""),
            "benchmark": display_name(rec),
            "value": f"{value:.6g}",
            "unit": unit_of(name),
            "compiler": rec.get("compiler", ""),
            "machine": f"{rec['host']} ({rec['nproc']} x {rec.get('cpu_model', '?')})",
            "regression": 1 if v["status"] == "regression" else 0,
            "noise_band_rel": f"{v['band']:.4f}" if v["band"] is not None else "",
        })
    return rows


# --------------------------------------------------------------------------
# 5. Plots: each benchmark's figure against commit
# --------------------------------------------------------------------------
def figure_of(rec: dict) -> tuple[str, float, float | None, float | None]:
    """(label, value, low, high) of the figure a plot shows: the first
    throughput counter (bounds scaled from the time range, since rate ~ 1/time
    for a fixed workload), else a memory counter, otherwise the real time."""
    t = rec["real_time_s"]
    counters = rec.get("counters", {})
    # Particle throughput first (the project's headline figure), then the rest by name.
    rates = sorted((k for k in counters if is_rate_counter(k)), key=lambda k: (not k.startswith("particle"), k))
    if rates:
        name = rates[0]
        value = counters[name]
        low = value * t["median"] / t["max"] if t.get("max") else None
        high = value * t["median"] / t["min"] if t.get("min") else None
        return name, value, low, high
    memory = sorted(k for k in counters if is_memory_counter(k))
    if memory:
        return memory[0], counters[memory[0]], None, None
    return "real_time_s", t["median"], t.get("min"), t.get("max")


def plot_file_name(executable: str, benchmark: str) -> str:
    return "trend_" + re.sub(r"[^A-Za-z0-9_.-]+", "_", f"{executable}__{benchmark}").strip("_") + ".png"


def plot_history(history: list[dict], out_dir: str | os.PathLike, host: str | None = None,
                 floor: float = DEFAULT_NOISE_FLOOR, time_kind: str = "real") -> list[dict]:
    """One PNG per (executable, benchmark) on one host, the figure against commit
    (one point per trend run, min-max bars). Returns the index rows it wrote."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if host is None and history:
        host = history[-1]["host"]
    series: dict[tuple, list[dict]] = {}
    flagged = {id(rec) for rec, v in verdicts_along_history(history, floor, time_kind) if v["status"] == "regression"}
    for rec in history:
        if rec["host"] == host:
            series.setdefault((rec["executable"], rec["benchmark"]), []).append(rec)
    index = []
    for (exe, bench), recs in sorted(series.items()):
        label = figure_of(recs[-1])[0]
        xs, ys, lo, hi, ticks, bad = [], [], [], [], [], []
        for i, rec in enumerate(recs):
            name, value, low, high = figure_of(rec)
            if name != label:
                continue
            xs.append(i)
            ys.append(value)
            lo.append(value - low if low is not None else 0.0)
            hi.append(high - value if high is not None else 0.0)
            ticks.append(rec["commit"] + ("+" if rec.get("dirty") else ""))
            if id(rec) in flagged:
                bad.append((i, value))
        fig, ax = plt.subplots(figsize=(6.4, 3.2))
        ax.errorbar(xs, ys, yerr=[lo, hi], marker="o", capsize=3, label="median, min-max of repeats")
        if bad:
            ax.plot([b[0] for b in bad], [b[1] for b in bad], "x", color="red", ms=10, mew=2,
                    label="regression beyond noise band")
        ax.legend(fontsize=7, loc="lower left")
        ax.set_xticks(xs)
        ax.set_xticklabels(ticks, rotation=45, ha="right", fontsize=7)
        ax.set_xlabel("commit (+ = uncommitted changes)")
        ax.set_ylabel(label)
        ax.set_title(f"{exe}: {bench}", fontsize=9)
        ax.set_ylim(bottom=0)
        ax.grid(alpha=0.3)
        fig.tight_layout()
        png = plot_file_name(exe, bench)
        fig.savefig(out_dir / png, dpi=100)
        plt.close(fig)
        index.append({"executable": exe, "benchmark": bench, "figure": label, "latest": ys[-1] if ys else "",
                      "commit": recs[-1]["commit"], "png": png})
    return index
