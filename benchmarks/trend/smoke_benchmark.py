#!/usr/bin/python3
"""Smoke test of one Google Benchmark executable: it lists its benchmarks, runs
one of them briefly (the first listed, or --filter) and writes JSON that
json.load reads and the trend tool can summarize (every benchmark with a finite
positive real time and no error). This is all the default test command runs of
a benchmark.

  smoke_benchmark.py EXE [--filter REGEX] [--min-time SECONDS]
"""
import argparse
import json
import re
import subprocess
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import trend  # noqa: E402


def main() -> int:
    p = argparse.ArgumentParser()
    p.add_argument("executable")
    p.add_argument("--filter", default=None, help="default: the first benchmark listed, exactly")
    p.add_argument("--min-time", default="0.001", help="--benchmark_min_time (seconds)")
    args = p.parse_args()

    listed = subprocess.run([args.executable, "--benchmark_list_tests=true"], capture_output=True,
                            text=True, check=True, timeout=60).stdout.split()
    if not listed:
        print(f"{args.executable}: lists no benchmark", file=sys.stderr)
        return 1
    flt = args.filter or "^" + re.escape(listed[0]) + "$"
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "smoke.json"
        cmd = [args.executable, f"--benchmark_filter={flt}", f"--benchmark_min_time={args.min_time}",
               "--benchmark_repetitions=1", f"--benchmark_out={out}", "--benchmark_out_format=json"]
        print("+", " ".join(cmd), flush=True)
        subprocess.run(cmd, check=True)
        with open(out, encoding="utf-8") as f:
            data = json.load(f)  # the claim: valid JSON
    summaries = trend.summarize(data, args.executable)  # raises on an error entry or a bad time
    if not summaries:
        print(f"{args.executable}: filter {flt} ran no benchmark", file=sys.stderr)
        return 1
    for s in summaries:
        print(f"ok {s['benchmark']}: {s['real_time_s']['median']:.3g} s, counters {s['counters']}")
    print(f"{len(listed)} benchmarks listed, {len(summaries)} run")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (subprocess.CalledProcessError, subprocess.TimeoutExpired, json.JSONDecodeError,
            trend.TrendError) as e:
        print(f"smoke_benchmark: {e}", file=sys.stderr)
        sys.exit(1)
