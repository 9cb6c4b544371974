#!/usr/bin/env python3
"""fdem on 1 and 2 MPI ranks, side by side with LIGGGHTS on 1 and 2, with the
communication volume per step, and the weak-scaling model built from them.

Cases (benchmarks/README.md, "Parallel runs"):
  P      the LIGGGHTS anchor scene P (28224 grains falling as a block, dry)
  B      the anchor scene B (4800 grains in a settled bed, dry)
  plume  verification/plume/plume.yaml (28224 grains, 12500 tetrahedra),
         reduced to its first --plume-end seconds
Each fdem run is `fdem run SCENE` (one process, one thread) or
`mpirun -n 2 fdem run SCENE` (one thread a rank), timed by fdem's own
end-of-run summary (wall minus output: the step loop, set-up excluded, as
LIGGGHTS' "Loop time"). The 2-rank runs preload libmpi_traffic.so
(mpi_traffic.c, built here with mpicc), which counts the bytes every rank
sends by kind of MPI call; fdem's own grain-exchange counters (ghosts,
migration), when it prints them, are read from its log. Runs are
interleaved in a random order per repetition so a drifting load hits all
alike; each waits up to --quiet-wait s for a quiet machine.

    benchmarks/parallel/parallel_scaling.py --build-dir build --reps 1

Writes BUILD/results/benchmarks/parallel_scaling.csv (one row per run) and
parallel_scaling.json (medians, per-rank costs and message sizes), prints a
markdown table, then the weak-scaling model (weak_scaling_model.py) at 64
and 1024 ranks for 1e7 and 1e8 grains from those numbers.
"""
import argparse
import csv
import json
import os
import random
import re
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "benchmarks" / "parallel"))
from quiet_machine import ensure_installed, wait_quiet  # noqa: E402
import weak_scaling_model  # noqa: E402

ANCHORS = (ROOT / ".." / "shared" / "anchors" / "liggghts").resolve()

# The anchors' scenes as fdem scenes: the contact law, step and walls of
# in.P / in.B (benchmarks/dem/bench_dem.cpp builds the same in code).
DRY_SCENES = {
    "P": dict(csv="P_init.csv", upper=[0.1, 0.1, 0.25], kn=100.0, cn=8.5e-4, dt=1e-5, steps=5000, grains=28224,
              liggghts="in.P"),
    "B": dict(csv="B_settled.csv", upper=[0.012, 0.0018, 0.012], kn=1e5, cn=0.026, dt=1e-7, steps=10000,
              grains=4800, liggghts="in.B"),
}

# DEM steps per driver step, as the plume's fluid step holds (Table 4): what
# happens once a driver step (probes, the grains gathered) is paid as often.
SUBCYCLES = 100

WALL = re.compile(r"fdem run: wall ([0-9.eE+-]+) s: fluid ([0-9.eE+-]+) s, DEM ([0-9.eE+-]+) s .*?coupling "
                  r"([0-9.eE+-]+) s, output ([0-9.eE+-]+) s")
EXCHANGE = re.compile(r"fdem run: grain exchange: (.*)")


def copy_inside_walls(source, target, upper):
    """The anchor CSV with every grain moved inside the walls: B's settled
    grains press on them by up to 4.2e-10 m (862 of 4800), which fdem's loader
    refuses as a sphere outside the domain. Each moves by at most its overlap
    (2e-6 of a diameter): the bed and its cost are the same."""
    with open(source) as f:
        rows = list(csv.DictReader(f))
        columns = list(rows[0].keys())
    for row in rows:
        radius = float(row["d"]) / 2
        for axis, hi in zip("xyz", upper):
            v = min(max(float(row[axis]), radius), hi - radius)
            row[axis] = repr(v)
    with open(target, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=columns)
        w.writeheader()
        w.writerows(rows)


def dry_scene(case, steps, directory):
    s = DRY_SCENES[case]
    copy_inside_walls(ANCHORS / "gen" / s["csv"], directory / s["csv"], s["upper"])
    lo, hi = [0, 0, 0], s["upper"]
    text = f"""# Anchor scene {case} (../shared/anchors/liggghts/in.{case}) for fdem run: written by parallel_scaling.py
title: anchor scene {case}
effects: {{fluid: false, gravity: true, normal_contact: true, walls: true}}
domain: {{lower: {lo}, upper: {hi}}}
gravity: [0, 0, -9.81]
particles:
  - {{name: grains, placement: csv, file: {s["csv"]}}}
contact: {{kn: {s["kn"]}, cn: {s["cn"]}, allow_unstable_step: true}}
time: {{dem_step: {s["dt"]}, subcycles: {SUBCYCLES}, end: {steps * s["dt"]:.12g}}}
output: {{vtu_interval: 0, csv_interval: {steps * s["dt"]:.12g}}}
"""
    path = directory / f"{case}.yaml"
    path.write_text(text)
    return path, steps


def plume_scene(end_s, directory):
    text = (ROOT / "verification" / "plume" / "plume.yaml").read_text()
    text, n = re.subn(r"(?m)^(\s*end:\s*)[0-9.eE+-]+", rf"\g<1>{end_s}", text)
    if n != 1:
        sys.exit("parallel_scaling: verification/plume/plume.yaml's time.end not found")
    text = re.sub(r"(?m)^(\s*vtu_interval:\s*)[0-9.eE+-]+", r"\g<1>0", text)
    # plume.yaml's projection scheme runs on one rank only: the ranks here
    # share the monolithic scheme's PETSc solve, settling.yaml's solver block.
    settling = (ROOT / "verification" / "settling" / "settling.yaml").read_text()
    block = re.search(r"(?ms)^  solver: \{.*?\}\n", settling)
    text, n = re.subn(r"(?m)^  scheme: projection\n", lambda _: block.group(0) if block else "", text)
    if n != 1 or not block:
        sys.exit("parallel_scaling: plume.yaml's 'scheme: projection' or settling.yaml's solver block not found")
    path = directory / "plume.yaml"
    path.write_text(text)
    # The plume's DEM step: 1e-5 s (plume.yaml, Table 4).
    return path, round(end_s / 1e-5)


def build_traffic_counter(directory):
    library = directory / "libmpi_traffic.so"
    subprocess.run(["mpicc", "-O2", "-shared", "-fPIC", "-o", str(library),
                    str(ROOT / "benchmarks" / "parallel" / "mpi_traffic.c")], check=True)
    return library


def run_fdem(fdem, scene, ranks, work, tag, traffic_library):
    out = work / f"out_{tag}"
    shutil.rmtree(out, ignore_errors=True)
    env = dict(os.environ, OMP_NUM_THREADS="1")
    prefix = work / f"traffic_{tag}"
    if ranks == 1:
        cmd = [str(fdem), "run", str(scene), "-o", str(out), "-q", "-t", "1"]
    else:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-n", str(ranks),
               "-x", "OMP_NUM_THREADS=1", "-x", f"LD_PRELOAD={traffic_library}", "-x", f"FDEM_MPI_TRAFFIC={prefix}",
               str(fdem), "run", str(scene), "-o", str(out), "-q"]
    started = time.time()
    done = subprocess.run(cmd, capture_output=True, text=True, env=env)
    elapsed = time.time() - started
    if done.returncode != 0:
        sys.exit(f"parallel_scaling: {' '.join(cmd)} failed ({done.returncode}):\n{done.stderr[-3000:]}")
    m = WALL.search(done.stderr)
    if not m:
        sys.exit(f"parallel_scaling: no wall-time summary in the log of {' '.join(cmd)}")
    wall, fluid, dem, coupling, output = (float(g) for g in m.groups())
    row = dict(loop_s=wall - output, fluid_s=fluid, dem_s=dem, coupling_s=coupling, elapsed_s=elapsed)
    exchange = EXCHANGE.search(done.stderr)
    row["exchange"] = exchange.group(1).strip() if exchange else ""
    row["traffic"] = read_traffic(prefix, ranks) if ranks > 1 else {}
    return row


def read_traffic(prefix, ranks):
    """kind -> (calls, bytes) summed over the ranks, and per rank."""
    total = {}
    for r in range(ranks):
        path = Path(f"{prefix}.{r}")
        if not path.exists():
            sys.exit(f"parallel_scaling: {path} missing (was libmpi_traffic.so preloaded?)")
        for line in path.read_text().split("\n"):
            if line.strip():
                kind, calls, nbytes = line.split()
                c, b = total.get(kind, (0, 0))
                total[kind] = (c + int(calls), b + int(nbytes))
    return total


def run_liggghts(case, ranks, steps, work):
    s = DRY_SCENES[case]
    log = work / f"liggghts_{case}_{ranks}.log"
    cmd = ["liggghts", "-in", s["liggghts"], "-screen", "none", "-log", str(log),
           "-var", "nsteps", str(steps), "-var", "thermoN", str(steps)]
    if ranks > 1:
        # The anchors' processor grid: px ranks along x.
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", str(ranks)] + cmd + ["-var", "px", str(ranks)]
    subprocess.run(cmd, check=True, cwd=work, capture_output=True)
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", log.read_text())
    if not m:
        sys.exit(f"parallel_scaling: no 'Loop time' line in {log}")
    return dict(loop_s=float(m.group(1)))


def median(rows, key):
    return statistics.median(r[key] for r in rows)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=str(ROOT / "build"))
    ap.add_argument("--reps", type=int, default=1)
    ap.add_argument("--cases", default="P,B,plume")
    ap.add_argument("--steps-fraction", type=float, default=1.0,
                    help="fraction of the anchors' step counts (P 5000, B 10000) to run (1: the anchors' own)")
    ap.add_argument("--plume-end", type=float, default=0.02, help="[s] of the plume to run (100 DEM steps a step)")
    ap.add_argument("--no-liggghts", action="store_true")
    ap.add_argument("--quiet-wait", type=float, default=0.0, help="max seconds to wait for a quiet machine per run")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--fdem", default=None, help="the fdem executable (default BUILD/solver/app/fdem)")
    args = ap.parse_args()

    fdem = Path(args.fdem) if args.fdem else Path(args.build_dir) / "solver" / "app" / "fdem"
    if not fdem.exists():
        sys.exit(f"parallel_scaling: {fdem} not built (cmake --build {args.build_dir} --target fdem)")
    ensure_installed(["mpirun", "mpicc"], "libopenmpi-dev", "parallel_scaling")
    cases = args.cases.split(",")
    with_liggghts = not args.no_liggghts and any(c in DRY_SCENES for c in cases)
    if with_liggghts:
        ensure_installed(["liggghts"], "liggghts", "parallel_scaling")
    rng = random.Random(args.seed)
    results_dir = Path(args.build_dir) / "results" / "benchmarks"
    results_dir.mkdir(parents=True, exist_ok=True)
    samples = {}  # (code, case, ranks) -> [row]
    loads = []
    with tempfile.TemporaryDirectory(prefix="fdem_parallel_") as tmp:
        work = Path(tmp)
        traffic = build_traffic_counter(work)
        if with_liggghts:
            for name in ("in.P", "in.B"):
                shutil.copy(ANCHORS / name, work / name)
            shutil.copytree(ANCHORS / "gen", work / "gen")
        scenes = {}
        for case in cases:
            if case in DRY_SCENES:
                steps = SUBCYCLES * max(1, round(DRY_SCENES[case]["steps"] * args.steps_fraction / SUBCYCLES))
                scenes[case] = dry_scene(case, steps, work)
            elif case == "plume":
                scenes[case] = plume_scene(args.plume_end, work)
            else:
                sys.exit(f"parallel_scaling: unknown case {case} (P, B, plume)")
        for rep in range(args.reps):
            runs = [("fdem", c, r) for c in cases for r in (1, 2)]
            if with_liggghts:
                runs += [("liggghts", c, r) for c in cases if c in DRY_SCENES for r in (1, 2)]
            rng.shuffle(runs)
            for code, case, ranks in runs:
                load = wait_quiet(args.quiet_wait) if args.quiet_wait > 0 else float("nan")
                loads.append(os.getloadavg()[0])
                scene, steps = scenes[case]
                if code == "fdem":
                    row = run_fdem(fdem, scene, ranks, work, f"{case}_{ranks}_{rep}", traffic)
                else:
                    row = run_liggghts(case, ranks, steps, work)
                row.update(code=code, case=case, ranks=ranks, rep=rep, steps=steps, load1=loads[-1], busy=load)
                samples.setdefault((code, case, ranks), []).append(row)
                print(f"  rep {rep + 1}: {code:8s} {case:5s} {ranks} rank(s)  loop {row['loop_s']:.3g} s  "
                      f"(load {loads[-1]:.1f})", flush=True)

    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    with open(results_dir / "parallel_scaling.csv.part", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["code", "case", "ranks", "rep", "steps", "loop_s", "fluid_s", "dem_s", "coupling_s", "load1",
                    "p2p_bytes", "allreduce_bytes", "allreduce_calls", "allgather_bytes", "exchange", "date"])
        for rows in samples.values():
            for r in rows:
                t = r.get("traffic", {})
                w.writerow([r["code"], r["case"], r["ranks"], r["rep"], r["steps"], f"{r['loop_s']:.6g}",
                            r.get("fluid_s", ""), r.get("dem_s", ""), r.get("coupling_s", ""), f"{r['load1']:.2f}",
                            t.get("p2p", (0, 0))[1], t.get("allreduce", (0, 0))[1], t.get("allreduce", (0, 0))[0],
                            t.get("allgather", (0, 0))[1], r.get("exchange", ""), stamp])
    (results_dir / "parallel_scaling.csv.part").replace(results_dir / "parallel_scaling.csv")

    print(f"\n{stamp}, {os.cpu_count()} cores, load average {min(loads):.1f}-{max(loads):.1f} during the runs, "
          f"{args.reps} repetition(s), medians; speed-up = loop time on 1 rank / on 2\n")
    print("| case | steps | fdem 1 rank [s] | fdem 2 ranks [s] | fdem speed-up | LIGGGHTS 1 [s] | LIGGGHTS 2 [s] | "
          "LIGGGHTS speed-up | bytes sent per DEM step, both ranks: p2p / allreduce / allgather | allreduces per DEM step |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    summary = {"date": stamp, "load_min": min(loads), "load_max": max(loads), "cases": {}}
    for case in cases:
        one, two = samples[("fdem", case, 1)], samples[("fdem", case, 2)]
        steps = one[0]["steps"]
        t1, t2 = median(one, "loop_s"), median(two, "loop_s")
        traffic = two[0]["traffic"]
        per_step = {k: traffic.get(k, (0, 0))[1] / steps for k in ("p2p", "allreduce", "allgather")}
        allreduces = traffic.get("allreduce", (0, 0))[0] / 2 / steps  # calls per rank
        lig = ("-", "-", "-")
        entry = dict(steps=steps, fdem_1=t1, fdem_2=t2, fdem_dem_1=median(one, "dem_s"), fdem_dem_2=median(two, "dem_s"),
                     bytes_per_step=per_step, allreduces_per_step_per_rank=allreduces, exchange=two[0]["exchange"],
                     grains=DRY_SCENES[case]["grains"] if case in DRY_SCENES else 28224)
        if ("liggghts", case, 1) in samples:
            l1, l2 = median(samples[("liggghts", case, 1)], "loop_s"), median(samples[("liggghts", case, 2)], "loop_s")
            lig = (f"{l1:.3g}", f"{l2:.3g}", f"{l1 / l2:.2f}")
            entry.update(liggghts_1=l1, liggghts_2=l2)
        summary["cases"][case] = entry
        print(f"| {case} | {steps} | {t1:.3g} | {t2:.3g} | {t1 / t2:.2f} | {lig[0]} | {lig[1]} | {lig[2]} | "
              f"{per_step['p2p']:.3g} / {per_step['allreduce']:.3g} / {per_step['allgather']:.3g} | {allreduces:.3g} |")
        if entry["exchange"]:
            print(f"|   | grain exchange (fdem's counters): {entry['exchange']} |||||||||")
    (results_dir / "parallel_scaling.json").write_text(json.dumps(summary, indent=1))
    print(f"\nwrote {results_dir / 'parallel_scaling.csv'} and parallel_scaling.json\n")
    if "B" in summary["cases"]:
        weak_scaling_model.print_model(summary)


if __name__ == "__main__":
    main()
