#!/usr/bin/env python3
"""fdem against LIGGGHTS 3.8 on the anchor scenes P and B, side by side.

Runs, for every repetition, the four cases (P and B, 1 and 2 threads) with
fdem's bench_dem and with LIGGGHTS (the anchors' in.P / in.B, 2 MPI ranks for
two threads), interleaved in a random order per repetition so a drifting load
hits both codes alike, and before each run waits (up to --quiet-wait s) until
other processes use less than 0.1 core. Prints a markdown table of medians
and writes CSV. Both sides time the same thing: the step loop, set-up
excluded (bench_dem times engine.run(); LIGGGHTS prints "Loop time").

    benchmarks/dem/side_by_side.py --build-dir build --reps 3

Needs /usr/bin/liggghts and mpirun (`apt-get install liggghts`, which this
script does when they are missing and it runs as root).
"""
import argparse
import csv
import json
import os
import platform
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
from quiet_machine import ensure_installed, wait_quiet  # noqa: E402
ANCHORS = (ROOT / ".." / "shared" / "anchors" / "liggghts").resolve()
# scene -> (bench_dem benchmark, LIGGGHTS input, steps, particles)
SCENES = {
    "P": ("BM_SceneP_SaltPlumeBlock", "in.P", 5000, 28224),
    "B": ("BM_SceneB_SettledBed", "in.B", 10000, 4800),
}


def ensure_liggghts():
    ensure_installed(["liggghts", "mpirun"], "liggghts", "side_by_side")


def run_fdem(bench, scene, threads):
    name = SCENES[scene][0]
    out = subprocess.run(
        [str(bench), f"--benchmark_filter=^{name}/{threads}/", "--benchmark_format=json"],
        check=True, capture_output=True, text=True, env=dict(os.environ, OMP_NUM_THREADS=str(threads)))
    rows = [b for b in json.loads(out.stdout)["benchmarks"] if b["name"].startswith(f"{name}/{threads}/")]
    if len(rows) != 1:
        sys.exit(f"side_by_side: bench_dem gave {len(rows)} rows for {name}/{threads}")
    return rows[0]["particle_steps_per_s"], int(rows[0]["rebuilds"])


def run_liggghts(workdir, scene, threads):
    _, infile, steps, particles = SCENES[scene]
    log = workdir / f"{scene}_{threads}.log"
    cmd = ["liggghts", "-in", infile, "-screen", "none", "-log", str(log),
           "-var", "nsteps", str(steps), "-var", "thermoN", str(steps)]
    if threads == 2:
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "-np", "2"] + cmd + ["-var", "px", "2"]
    subprocess.run(cmd, check=True, cwd=workdir, capture_output=True)
    text = log.read_text()
    m = re.search(r"Loop time of ([0-9.eE+-]+) on (\d+) procs for (\d+) steps with (\d+) atoms", text)
    if not m:
        sys.exit(f"side_by_side: no 'Loop time' line in {log}")
    builds = re.search(r"Neighbor list builds = (\d+)", text)
    loop_s, atoms, nsteps = float(m.group(1)), int(m.group(4)), int(m.group(3))
    return atoms * nsteps / loop_s, int(builds.group(1)) if builds else -1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=str(ROOT / "build"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--cases", default="P1,P2,B1,B2", help="scene letter + thread count, comma separated")
    ap.add_argument("--quiet-wait", type=float, default=120.0, help="max seconds to wait for a quiet machine per run")
    ap.add_argument("--out", default=None, help="CSV path (default BUILD/results/benchmarks/dem_vs_liggghts.csv)")
    ap.add_argument("--seed", type=int, default=1)
    args = ap.parse_args()

    bench = Path(args.build_dir) / "benchmarks" / "dem" / "bench_dem"
    if not bench.exists():
        sys.exit(f"side_by_side: {bench} not built (cmake --build {args.build_dir} --target bench_dem)")
    ensure_liggghts()
    cases = [(c[0], int(c[1:])) for c in args.cases.split(",")]
    rng = random.Random(args.seed)
    samples = {}  # (code, scene, threads) -> list of (rate, rebuilds, foreign load)
    with tempfile.TemporaryDirectory(prefix="fdem_liggghts_") as tmp:
        work = Path(tmp)
        for name in ("in.P", "in.B"):
            shutil.copy(ANCHORS / name, work / name)
        shutil.copytree(ANCHORS / "gen", work / "gen")
        for rep in range(args.reps):
            runs = [(code, scene, threads) for scene, threads in cases for code in ("fdem", "liggghts")]
            rng.shuffle(runs)
            for code, scene, threads in runs:
                load = wait_quiet(args.quiet_wait)
                if code == "fdem":
                    rate, builds = run_fdem(bench, scene, threads)
                else:
                    rate, builds = run_liggghts(work, scene, threads)
                samples.setdefault((code, scene, threads), []).append((rate, builds, load))
                print(f"  rep {rep + 1}: {code:8s} {scene}{threads}  {rate:.3e} particle-steps/s  "
                      f"{builds} list builds  (busy before: {load:.2f} cores)", flush=True)

    out = Path(args.out) if args.out else Path(args.build_dir) / "results" / "benchmarks" / "dem_vs_liggghts.csv"
    out.parent.mkdir(parents=True, exist_ok=True)
    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    print(f"\n{stamp}, {platform.node()}, {os.cpu_count()} cores, {args.reps} repetitions, medians:\n")
    print("| scene | threads | fdem particle-steps/s | LIGGGHTS particle-steps/s | ratio | fdem spread | LIGGGHTS spread | list builds fdem / LIGGGHTS |")
    print("|---|---|---|---|---|---|---|---|")
    tmp_out = out.with_suffix(".csv.part")
    with open(tmp_out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["scene", "threads", "fdem_particle_steps_per_s", "liggghts_particle_steps_per_s", "ratio",
                    "fdem_spread", "liggghts_spread", "fdem_list_builds", "liggghts_list_builds", "reps", "date"])
        for scene, threads in cases:
            a = samples[("fdem", scene, threads)]
            b = samples[("liggghts", scene, threads)]
            ma, mb = statistics.median(r for r, _, _ in a), statistics.median(r for r, _, _ in b)
            sa = (max(r for r, _, _ in a) - min(r for r, _, _ in a)) / ma
            sb = (max(r for r, _, _ in b) - min(r for r, _, _ in b)) / mb
            print(f"| {scene} | {threads} | {ma:.3e} | {mb:.3e} | {ma / mb:.2f} | {sa:.0%} | {sb:.0%} | "
                  f"{a[0][1]} / {b[0][1]} |")
            w.writerow([scene, threads, f"{ma:.6g}", f"{mb:.6g}", f"{ma / mb:.4g}", f"{sa:.3g}", f"{sb:.3g}",
                        a[0][1], b[0][1], len(a), stamp])
    tmp_out.replace(out)  # whole file or none
    print(f"\nwrote {out}")


if __name__ == "__main__":
    main()
