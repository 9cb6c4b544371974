#!/usr/bin/python3
"""Verdict of the effects benchmark: does a scene with an effect off run as
fast as the same physics written without it, within the noise of the machine?

Runs bench_effects with repetitions (median of repeats), compares each DemEngine
and Simulation variant with the hand-written reference (normal contact only, no
effect machinery) at the same thread count, and prints:
  variant, threads, particle-steps/s (median), ratio to the reference, band, verdict
where band = max(noise floor, repeat spread of either figure) as in the trend
tool (benchmarks/trend/trend.py), and the heap bytes per particle with
tangential contact off and on. Writes the table as CSV to --csv when given.

  compare_effects.py BENCH_EFFECTS [--repetitions 5] [--min-time 0.3] [--csv FILE]
"""
import argparse
import csv
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "trend"))
import trend  # noqa: E402

OFF_VARIANTS = ("engine_normal_only", "simulation_fluid_off")  # must match the reference


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("executable")
    p.add_argument("--repetitions", type=int, default=5)
    p.add_argument("--min-time", type=float, default=0.3)
    p.add_argument("--noise-floor", type=float, default=trend.DEFAULT_NOISE_FLOOR)
    p.add_argument("--csv", default=None)
    args = p.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "effects.json"
        r = subprocess.run([args.executable, f"--benchmark_repetitions={args.repetitions}",
                        f"--benchmark_min_time={args.min_time}", f"--benchmark_out={out}",
                        # repetitions of all variants in random order: load that drifts
                        # during the run hits the reference and the variants alike
                        "--benchmark_enable_random_interleaving=true",
                        "--benchmark_out_format=json"], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if r.returncode != 0:
            print(r.stderr, file=sys.stderr)
            return 2
        data = trend.load_benchmark_json(out)
    runs = {s["benchmark"]: s for s in trend.summarize(data, args.executable)}

    rows = []
    for name, s in runs.items():
        if not name.startswith("BM_Effects_"):
            continue
        variant, threads = name[len("BM_Effects_"):].split("/")[0], name.split("omp:")[1].split("/")[0]
        ref = runs.get(f"BM_Effects_reference_normal_only/omp:{threads}/real_time")
        rate = s["counters"]["particle_steps_per_s"]
        ref_rate = ref["counters"]["particle_steps_per_s"]
        ratio = rate / ref_rate
        band = trend.noise_band(ref, s, args.noise_floor)
        if variant == "reference_normal_only":
            verdict = "reference"
        elif ratio < 1.0 / (1.0 + band):
            verdict = "slower than reference" if variant in OFF_VARIANTS else f"effect costs x{1 / ratio:.2f}"
        elif ratio > 1.0 + band:
            verdict = "faster than reference"
        else:
            verdict = "within noise" if variant in OFF_VARIANTS else "effect cost within noise"
        rows.append({"variant": variant, "threads": threads, "particle_steps_per_s": f"{rate:.4g}",
                     "spread": f"{s['spread']:.3f}", "ratio_to_reference": f"{ratio:.3f}",
                     "band": f"{band:.3f}", "verdict": verdict})
    order = ["reference_normal_only", "engine_normal_only", "simulation_fluid_off", "engine_rotation",
             "engine_tangential", "engine_tangential_rotation"]
    rows.sort(key=lambda r: (int(r["threads"]), order.index(r["variant"]) if r["variant"] in order else len(order)))
    print(f"{'variant':<28} {'omp':>3} {'p-steps/s':>11} {'spread':>7} {'ratio':>6} {'band':>6}  verdict")
    for r in rows:
        print(f"{r['variant']:<28} {r['threads']:>3} {r['particle_steps_per_s']:>11} {r['spread']:>7} "
              f"{r['ratio_to_reference']:>6} {r['band']:>6}  {r['verdict']}")
    mem = {s["benchmark"]: s["counters"]["bytes_per_particle"] for s in runs.values()
           if s["benchmark"].startswith("BM_MemoryPerParticle")}
    off = next(v for k, v in mem.items() if "tangential:0" in k)
    on = next(v for k, v in mem.items() if "tangential:1" in k)
    print(f"heap per particle: tangential off {off:.0f} B, on {on:.0f} B "
          f"(slip history and its bookkeeping: {on - off:.0f} B, {100 * (1 - off / on):.0f} % saved when off)")
    if args.csv:
        Path(args.csv).parent.mkdir(parents=True, exist_ok=True)
        with open(args.csv, "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(rows[0]))
            w.writeheader()
            w.writerows(rows)
    return 0


if __name__ == "__main__":
    sys.exit(main())
