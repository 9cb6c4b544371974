#!/usr/bin/env python3
"""fdem against OpenFOAM's DPMFoam on the single-particle settling scene, side by side.

The scene (paper Sect. 4.1): one 0.76 mm grain settling 1 s in a closed
44 x 44 x 80 mm water column, 11 x 11 x 20 cells, fluid step 0.01 s,
two-way coupled. fdem runs verification/settling/settling.yaml (12100
tetrahedra, 1000 DEM subcycles a step); DPMFoam runs the anchor case
../shared/anchors/openfoam/settling (the same box, cells and step,
ErgunWenYuDrag; README there). Both are one process on one core, or with
--ranks N both run on N MPI ranks (fdem: `mpirun -n N fdem run`, its
fluid's rows shared; DPMFoam: decomposePar into N subdomains, simple
split along z like fdem's slabs, then `mpirun -np N DPMFoam -parallel`;
decomposePar, like blockMesh, is not timed).

--scheme projection runs fdem's scene with fluid.scheme: projection (the
segregated step of solver/fluid/projection_scheme.hpp, a copy of
settling.yaml with its PETSc solver block replaced by that key); with
--baseline-scene verification/settling/settling.yaml the same binary runs
the paper's monolithic scheme beside it in the same repetitions.

Every repetition runs both codes in a random order, so a drifting load hits
both alike; before each run the script waits (up to --quiet-wait s) until
other processes use less than 0.1 core, and it records how busy the machine
was. Each code is timed as a whole process (wall and CPU seconds of the
child: set-up, the 100 steps, output). DPMFoam's blockMesh runs before and
is not timed. fdem's own breakdown (its "fdem run: wall ... fluid ... DEM"
line) is kept beside it. Prints a markdown table of medians and writes CSV.

    benchmarks/fluid/settling_vs_dpmfoam.py --build-dir build --reps 3

Needs /usr/bin/DPMFoam and blockMesh (Debian's `openfoam`, v1912, which this
script installs with apt-get when they are missing and it runs as root).
"""
import argparse
import csv
import os
import platform
import random
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "benchmarks"))
from quiet_machine import busy_cores, ensure_installed, wait_quiet  # noqa: E402
ANCHOR = (ROOT / ".." / "shared" / "anchors" / "openfoam" / "settling").resolve()
SCENE = ROOT / "verification" / "settling" / "settling.yaml"
FLUID_STEP_S = 0.01  # the scene's time.fluid_step, the anchor's deltaT


def ensure_openfoam():
    ensure_installed(["DPMFoam", "blockMesh"], "openfoam", "settling_vs_dpmfoam")


def timed(cmd, **kwargs):
    """Runs cmd; returns (wall s, child CPU s, busy cores of everything else during the run, stdout+stderr)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    b0 = busy_cores()
    t0 = time.perf_counter()
    out = subprocess.run(cmd, check=True, capture_output=True, text=True, **kwargs)
    wall = time.perf_counter() - t0
    busy = busy_cores() - b0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, max(0.0, (busy - cpu) / wall), out.stdout + out.stderr


def mpirun(ranks):
    return ["mpirun", "--allow-run-as-root", "-n", str(ranks), "-x", "OMP_NUM_THREADS=1"] if ranks > 1 else []


def projection_scene(work):
    """settling.yaml with fluid.scheme: projection in place of its fluid.solver block."""
    text, count = re.subn(r"(?ms)^  solver: \{.*?\}\n", "  scheme: projection\n", SCENE.read_text())
    if count != 1:
        sys.exit(f"settling_vs_dpmfoam: {SCENE}: no single 'fluid.solver' block to replace with scheme: projection")
    out = work / "settling_projection.yaml"
    out.write_text(text)
    return out


def run_fdem(fdem, work, rep, scene=SCENE, tag="fdem", ranks=1):
    outdir = work / f"{tag}_{rep}"
    wall, cpu, others, text = timed(mpirun(ranks) + [str(fdem), "run", str(scene), "--output", str(outdir), "--quiet",
                                                      "--threads", "1", "--overwrite"],
                                    env=dict(os.environ, OMP_NUM_THREADS="1"))
    m = re.search(r"fdem run: wall ([0-9.eE+-]+) s: fluid ([0-9.eE+-]+) s, DEM ([0-9.eE+-]+) s", text)
    if not m:
        sys.exit(f"settling_vs_dpmfoam: no 'fdem run: wall' line in fdem's output:\n{text}")
    return wall, cpu, others, float(m.group(2)), float(m.group(3))


def decompose_par_dict(ranks):
    """N subdomains stacked along z (the column's long axis), as fdem's slabs."""
    return ("FoamFile { version 2.0; format ascii; class dictionary; object decomposeParDict; }\n"
            f"numberOfSubdomains {ranks};\nmethod simple;\n"
            f"simpleCoeffs {{ n (1 1 {ranks}); delta 0.001; }}\n")


def prepare_dpmfoam(work, rep, ranks=1):
    case = work / f"dpmfoam_{rep}"
    shutil.copytree(ANCHOR, case)
    props = case / "constant" / "kinematicCloudProperties"
    props.write_text(props.read_text().replace("DRAGMODEL", "ErgunWenYuDrag { alphac alpha.water; }"))
    control = case / "system" / "controlDict"
    control.write_text(re.sub(r"(?m)^deltaT .*$", f"deltaT          {FLUID_STEP_S};", control.read_text()))
    env = dict(os.environ, WM_PROJECT_DIR="/usr/share/openfoam")  # all the Debian binaries need
    subprocess.run(["blockMesh"], check=True, cwd=case, capture_output=True, env=env)
    if ranks > 1:
        (case / "system" / "decomposeParDict").write_text(decompose_par_dict(ranks))
        subprocess.run(["decomposePar", "-force"], check=True, cwd=case, capture_output=True, env=env)
    return case, env


def run_dpmfoam(work, rep, ranks=1):
    case, env = prepare_dpmfoam(work, rep, ranks)
    cmd = mpirun(ranks) + ["-x", "WM_PROJECT_DIR", "DPMFoam", "-parallel"] if ranks > 1 else ["DPMFoam"]
    wall, cpu, others, text = timed(cmd, cwd=case, env=env)
    if not re.search(r"(?m)^End\s*$", text):
        sys.exit(f"settling_vs_dpmfoam: DPMFoam did not reach its end time in {case}")
    return wall, cpu, others


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--build-dir", default=str(ROOT / "build"))
    ap.add_argument("--reps", type=int, default=3)
    ap.add_argument("--quiet-wait", type=float, default=60.0, help="max seconds to wait for a quiet machine per run")
    ap.add_argument("--out", default=None, help="CSV path (default BUILD/results/benchmarks/settling_vs_dpmfoam.csv, "
                    "settling_vs_dpmfoam_rN.csv with --ranks N > 1)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--ranks", type=int, default=1, help="MPI ranks of both codes (default 1: one process each)")
    ap.add_argument("--scheme", choices=["monolithic", "projection"], default="monolithic",
                    help="fdem's fluid.scheme (default the scene's monolithic; projection runs on one rank only)")
    ap.add_argument("--baseline", default=None,
                    help="another fdem binary (e.g. main's) run interleaved with the two, for a before/after ratio")
    ap.add_argument("--baseline-scene", default=None,
                    help="the scene the baseline runs (default the same settling.yaml; with it and no --baseline, "
                         "this build's fdem runs it: a before/after of a scene change, e.g. its fluid.solver)")
    args = ap.parse_args()

    fdem = Path(args.build_dir) / "solver" / "app" / "fdem"
    if not fdem.exists():
        sys.exit(f"settling_vs_dpmfoam: {fdem} not built (cmake --build {args.build_dir} --target fdem)")
    ensure_openfoam()
    if args.ranks < 1:
        sys.exit(f"settling_vs_dpmfoam: --ranks {args.ranks}: at least 1")
    if args.scheme == "projection" and args.ranks > 1:
        sys.exit("settling_vs_dpmfoam: --scheme projection runs on one rank only")
    if args.ranks > 1:
        ensure_installed(["mpirun"], "openmpi-bin", "settling_vs_dpmfoam")
    rng = random.Random(args.seed)
    fdem_rows, foam_rows, base_rows = [], [], []
    baseline = Path(args.baseline) if args.baseline else (fdem if args.baseline_scene else None)
    baseline_scene = Path(args.baseline_scene).resolve() if args.baseline_scene else SCENE
    with tempfile.TemporaryDirectory(prefix="fdem_dpmfoam_") as tmp:
        work = Path(tmp)
        scene = projection_scene(work) if args.scheme == "projection" else SCENE
        for rep in range(args.reps):
            order = ["fdem", "dpmfoam"] + (["baseline"] if baseline else [])
            rng.shuffle(order)
            for code in order:
                quiet = wait_quiet(args.quiet_wait)
                if code in ("fdem", "baseline"):
                    wall, cpu, others, fluid, dem = (run_fdem(fdem, work, rep, scene, ranks=args.ranks) if code == "fdem" else
                                                     run_fdem(baseline, work, rep, baseline_scene, "baseline",
                                                              args.ranks))
                    (fdem_rows if code == "fdem" else base_rows).append((wall, cpu, others, quiet, fluid, dem))
                    extra = f", fluid {fluid:.2f} s, DEM {dem:.2f} s"
                else:
                    wall, cpu, others = run_dpmfoam(work, rep, args.ranks)
                    foam_rows.append((wall, cpu, others, quiet))
                    extra = ""
                print(f"  rep {rep + 1}: {code:8s} wall {wall:.2f} s, CPU {cpu:.2f} s{extra} "
                      f"(other processes: {quiet:.2f} cores before, {others:.2f} during)", flush=True)

    med = lambda rows, i: statistics.median(r[i] for r in rows)
    stamp = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    load_during = statistics.median([r[2] for r in fdem_rows + foam_rows + base_rows])
    print(f"\n{stamp}, {platform.node()}, {os.cpu_count()} cores, {args.ranks} rank(s) each, {args.reps} repetitions, medians; "
          f"other processes kept {load_during:.2f} cores busy (median over the runs):\n")
    print("| code | wall [s] | CPU [s] | fluid [s] | DEM [s] |")
    print("|---|---|---|---|---|")
    print(f"| fdem ({args.scheme}) | {med(fdem_rows, 0):.2f} | {med(fdem_rows, 1):.2f} | {med(fdem_rows, 4):.2f} | "
          f"{med(fdem_rows, 5):.2f} |")
    if base_rows:
        print(f"| fdem baseline ({baseline}, {baseline_scene.name}) | {med(base_rows, 0):.2f} | {med(base_rows, 1):.2f} | "
              f"{med(base_rows, 4):.2f} | {med(base_rows, 5):.2f} |")
    print(f"| DPMFoam | {med(foam_rows, 0):.2f} | {med(foam_rows, 1):.2f} | | |")
    wall_ratio = med(fdem_rows, 0) / med(foam_rows, 0)
    cpu_ratio = med(fdem_rows, 1) / med(foam_rows, 1)
    print(f"\nfdem / DPMFoam: wall {wall_ratio:.2f}, CPU {cpu_ratio:.2f}")
    if base_rows:
        print(f"fdem / baseline: wall {med(fdem_rows, 0) / med(base_rows, 0):.2f}, "
              f"CPU {med(fdem_rows, 1) / med(base_rows, 1):.2f}, fluid {med(fdem_rows, 4) / med(base_rows, 4):.2f}")

    name = "settling_vs_dpmfoam.csv" if args.ranks == 1 else f"settling_vs_dpmfoam_r{args.ranks}.csv"
    if args.scheme == "projection":
        name = name.replace(".csv", "_projection.csv")
    out = Path(args.out) if args.out else Path(args.build_dir) / "results" / "benchmarks" / name
    out.parent.mkdir(parents=True, exist_ok=True)
    tmp_out = out.with_suffix(".csv.part")
    with open(tmp_out, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["code", "wall_s", "cpu_s", "fluid_s", "dem_s", "wall_ratio", "cpu_ratio", "other_cores_busy",
                    "reps", "date", "host"])
        w.writerow(["fdem" if args.scheme == "monolithic" else "fdem_projection", f"{med(fdem_rows, 0):.4g}", f"{med(fdem_rows, 1):.4g}", f"{med(fdem_rows, 4):.4g}",
                    f"{med(fdem_rows, 5):.4g}", f"{wall_ratio:.4g}", f"{cpu_ratio:.4g}", f"{load_during:.3g}",
                    args.reps, stamp, platform.node()])
        w.writerow(["dpmfoam", f"{med(foam_rows, 0):.4g}", f"{med(foam_rows, 1):.4g}", "", "", "", "",
                    f"{load_during:.3g}", args.reps, stamp, platform.node()])
    tmp_out.replace(out)  # whole file or none
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
