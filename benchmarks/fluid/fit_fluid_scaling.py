#!/usr/bin/env python3
"""Fitted cost exponents of the fluid step from bench_fluid's JSON output.

Reads the BM_FluidSolverScaling/<solver>/<n> rows of a Google Benchmark JSON
file (bench_fluid --benchmark_out=FILE --benchmark_out_format=json), and for
each solver fits CPU time per step ~ N^k over the meshes (least squares in
log-log, N = tetrahedra) and prints k with the Krylov iterations per step.
With --benchmark_repetitions the median of each mesh is used.

Usage: fit_fluid_scaling.py bench_fluid.json
"""
import json
import math
import statistics
import sys
from collections import defaultdict


def main(path):
    with open(path) as f:
        rows = json.load(f)["benchmarks"]
    runs = defaultdict(lambda: defaultdict(list))  # solver -> tetrahedra -> [(cpu_ms, krylov)]
    for row in rows:
        name = row.get("run_name", row["name"])
        if not name.startswith("BM_FluidSolverScaling/") or row.get("run_type") == "aggregate":
            continue
        solver = name.split("/")[1]
        scale = {"ns": 1e-6, "us": 1e-3, "ms": 1.0, "s": 1e3}[row.get("time_unit", "ns")]
        runs[solver][int(row["elements"])].append((row["cpu_time"] * scale, row["krylov_per_step"]))
    if not runs:
        sys.exit(f"{path}: no BM_FluidSolverScaling rows")
    for solver, by_mesh in sorted(runs.items()):
        meshes = sorted(by_mesh)
        cpu = [statistics.median(t for t, _ in by_mesh[n]) for n in meshes]
        krylov = [statistics.median(k for _, k in by_mesh[n]) for n in meshes]
        x = [math.log(n) for n in meshes]
        y = [math.log(t) for t in cpu]
        mx, my = statistics.fmean(x), statistics.fmean(y)
        k = sum((a - mx) * (b - my) for a, b in zip(x, y)) / sum((a - mx) ** 2 for a in x) if len(x) > 1 else float("nan")
        table = ", ".join(f"{n}: {t:.3g} ms / {it:.1f} Krylov" for n, t, it in zip(meshes, cpu, krylov))
        print(f"{solver}: CPU per step ~ N^{k:.2f} ({table})")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    main(sys.argv[1])
