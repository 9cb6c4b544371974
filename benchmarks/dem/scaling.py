#!/usr/bin/python3
"""Cost against problem size (benchmarks/README.md, "Scaling"): dry DEM from 1e3 to 1e6
particles, one and two threads, the fitted exponent and the two-thread
speed-up; and the fluid step on cubes of 1e3 to 1e5 tetrahedra
(bench_fluid's BM_FluidStep/<n>/<threads>), the same way.

  /usr/bin/python3 benchmarks/dem/scaling.py --build-dir build            # ~1 min on a quiet machine
  ... --no-1e6 --no-fluid                                                 # DEM 1e3..3e5 only, ~15 s
  ... --threads 1                                                         # one thread only
  ... --fluid-large                                                       # + 1e6 tets (minutes per step)

1e6 particles are registered in bench_dem only with FDEM_BENCH_DEM_LARGE=1
(this script sets it unless --no-1e6), so the trend command's runs of every
benchmark stay short.

Cases (bench_dem.cpp, "Scaling"): `dem_dense`, a lattice of touching
0.25 mm spheres with small random offsets and walls, scene B's Kn, Cn, dt
(~1.8 contacts per grain); `dem_gas`, the same at spacing 4 d (no contacts).
The time of one step is the benchmark's real time per iteration over its
steps; the cost per particle-step is that over N. The exponent is the
least-squares slope of log(time per step) against log(N): 1 is linear
(O(N)); the cost per particle-step then goes as N^(exponent - 1).

Writes `$RESULTS/benchmarks/scaling.csv` (reports/FORMATS.md, `--out` to
change) and prints the table. Single-thread rows also carry the CPU time of
the main thread (steadier on a shared machine, README.md "Trend command");
two-thread rows are only meaningful on a quiet machine.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# benchmark name prefix -> (case, size counter, what the size counts, steps counter or None = 1 step)
CASES = {
    "BM_Scaling_DenseLattice": ("dem_dense", "particles", "particles", "steps_per_iteration"),
    "BM_Scaling_Gas": ("dem_gas", "particles", "particles", "steps_per_iteration"),
    "BM_FluidStep": ("fluid_step", "elements", "tets", None),
    "BM_FluidStepLarge": ("fluid_step", "elements", "tets", None),
}
UNIT_S = {"ns": 1e-9, "us": 1e-6, "ms": 1e-3, "s": 1.0}


def run_benchmark(exe: Path, filt: str, env: dict[str, str]) -> dict:
    with tempfile.NamedTemporaryFile(suffix=".json", delete=False) as tmp:
        out = Path(tmp.name)
    try:
        cmd = [str(exe), f"--benchmark_filter={filt}", f"--benchmark_out={out}", "--benchmark_out_format=json"]
        print("running:", " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True, env=env, stdout=subprocess.DEVNULL)
        return json.loads(out.read_text())
    finally:
        out.unlink(missing_ok=True)


def rows_from(report: dict) -> list[dict]:
    rows = []
    load = report.get("context", {}).get("load_avg", [float("nan")])[0]
    for b in report.get("benchmarks", []):
        if b.get("run_type", "iteration") != "iteration" or b.get("error_occurred"):
            continue
        prefix = b["name"].split("/")[0]
        if prefix not in CASES:
            continue
        case, size_key, unit, steps_key = CASES[prefix]
        steps = float(b[steps_key]) if steps_key else 1.0
        scale = UNIT_S[b.get("time_unit", "ns")]
        size = float(b[size_key])
        # <prefix>/<size argument>/<OpenMP threads>/...: the name, not the
        # "threads" key, which a counter of the same name shadows in the JSON.
        threads = int(b["name"].split("/")[2])
        rows.append({
            "case": case, "size": size, "unit": unit, "threads": threads,
            "seconds_per_step": b["real_time"] * scale / steps,
            "cpu_seconds_per_step": b["cpu_time"] * scale / steps,
            "load_average": load,
        })
    return rows


def fit_exponent(sizes: list[float], times: list[float]) -> float | None:
    """Least-squares slope of log(time) against log(size)."""
    pts = [(math.log(s), math.log(t)) for s, t in zip(sizes, times) if s > 0 and t > 0]
    if len(pts) < 2:
        return None
    mx = sum(x for x, _ in pts) / len(pts)
    my = sum(y for _, y in pts) / len(pts)
    sxx = sum((x - mx) ** 2 for x, _ in pts)
    return sum((x - mx) * (y - my) for x, y in pts) / sxx if sxx > 0 else None


def write_csv(path: Path, rows: list[dict]) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    cols = ["case", "size", "unit", "threads", "seconds_per_step", "cpu_seconds_per_step", "load_average"]
    text = "# benchmarks/dem/scaling.py: time of one step against problem size (bench_dem, bench_fluid)\n"
    text += ",".join(cols) + "\n"
    for r in rows:
        text += ",".join(f"{r[c]:.6g}" if isinstance(r[c], float) else str(r[c]) for c in cols) + "\n"
    tmp = path.with_suffix(".csv.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)  # atomic: the report may read the folder meanwhile


def print_table(rows: list[dict]) -> None:
    for case in dict.fromkeys(r["case"] for r in rows):
        sel = [r for r in rows if r["case"] == case]
        unit = sel[0]["unit"]
        threads = sorted({r["threads"] for r in sel})
        print(f"\n{case}: seconds per step and ns per {unit[:-1]}-step (CPU ns for 1 thread in brackets)")
        head = f"{'N':>9} " + " ".join(f"{f'{t} thr s/step':>13} {f'{t} thr ns/item':>22}" for t in threads)
        print(head + ("  speed-up 2/1" if set(threads) >= {1, 2} else ""))
        for size in sorted({r["size"] for r in sel}):
            line = f"{size:9.0f} "
            by_t = {r["threads"]: r for r in sel if r["size"] == size}
            for t in threads:
                r = by_t.get(t)
                if not r:
                    line += f"{'-':>13} {'-':>22} "
                    continue
                ns = 1e9 * r["seconds_per_step"] / size
                cpu = f" ({1e9 * r['cpu_seconds_per_step'] / size:.3g})" if t == 1 else ""
                line += f"{r['seconds_per_step']:13.4g} {f'{ns:.3g}{cpu}':>22} "
            if 1 in by_t and 2 in by_t:
                line += f"  {by_t[1]['seconds_per_step'] / by_t[2]['seconds_per_step']:.2f}"
            print(line)
        for t in threads:
            s = sorted((r["size"], r["seconds_per_step"]) for r in sel if r["threads"] == t)
            p = fit_exponent([a for a, _ in s], [b for _, b in s])
            if p is not None:
                c = sorted((r["size"], r["cpu_seconds_per_step"]) for r in sel if r["threads"] == t)
                pc = fit_exponent([a for a, _ in c], [b for _, b in c]) if t == 1 else None
                cpu = f"; CPU time ~ N^{pc:.3f}" if pc is not None else ""
                print(f"  {t} thread(s): time per step ~ N^{p:.3f} (cost per {unit[:-1]}-step ~ N^{p - 1:+.3f}){cpu}, "
                      f"N = {s[0][0]:.0f}..{s[-1][0]:.0f}, least squares in log-log over {len(s)} sizes")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", type=Path, default=ROOT / "build")
    ap.add_argument("--out", type=Path, help="CSV (default BUILD/results/benchmarks/scaling.csv)")
    ap.add_argument("--no-1e6", dest="large", action="store_false", help="leave out 1e6 particles")
    ap.add_argument("--no-fluid", dest="fluid", action="store_false", help="leave out bench_fluid's BM_FluidStep")
    ap.add_argument("--fluid-large", action="store_true", help="add 1e6 tets (FDEM_BENCH_FLUID_LARGE=1)")
    ap.add_argument("--threads", default="1,2", help="thread counts, e.g. 1 (default 1,2)")
    ap.add_argument("--from-json", type=Path, nargs="*", help="tabulate benchmark JSON files instead of running")
    args = ap.parse_args()
    threads = {int(t) for t in args.threads.split(",")}
    reports = []
    if args.from_json:
        reports = [json.loads(p.read_text()) for p in args.from_json]
    else:
        env = dict(os.environ)
        if args.large:
            env["FDEM_BENCH_DEM_LARGE"] = "1"
        if args.fluid_large:
            env["FDEM_BENCH_FLUID_LARGE"] = "1"
        tsel = "|".join(str(t) for t in sorted(threads))
        reports.append(run_benchmark(args.build_dir / "benchmarks/dem/bench_dem",
                                     f"^BM_Scaling_.*/[0-9]+/({tsel})/", env))
        fluid_exe = args.build_dir / "benchmarks/fluid/bench_fluid"
        if args.fluid and not fluid_exe.exists():
            print(f"scaling: {fluid_exe} not built, fluid left out", file=sys.stderr)
        elif args.fluid:
            large = "|BM_FluidStepLarge" if args.fluid_large else ""
            reports.append(run_benchmark(fluid_exe,
                                         f"^(BM_FluidStep{large})/[0-9]+/({tsel})/", env))
    rows = [r for rep in reports for r in rows_from(rep) if r["threads"] in threads]
    if not rows:
        print("scaling: no benchmark rows", file=sys.stderr)
        return 1
    rows.sort(key=lambda r: (r["case"], r["threads"], r["size"]))
    out = args.out or args.build_dir / "results/benchmarks/scaling.csv"
    write_csv(out, rows)
    print_table(rows)
    print(f"\nwrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
