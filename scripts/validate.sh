#!/usr/bin/env bash
# The README's main job: build, run the fast verification tier, write the report.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/build.sh"
build="${BUILD_DIR:-$root/build}"
# Label main: the studies too long for the fast tier at the size the main job affords (the channel to 1.0 s).
(cd "$build" && ctest --output-on-failure -L 'verification|main' -LE nightly --parallel "${JOBS:-$(nproc)}")
# The benchmark history as the report's trend table (no benchmark is run here).
/usr/bin/python3 "$root/benchmarks/trend/run_trend.py" --build-dir "$build" --no-plot plot > /dev/null || true
if [ -f "$root/reports/generate.py" ]; then
  /usr/bin/python3 "$root/reports/generate.py" --results "$build/results" --build-info "$build/build_info.json" --out "$root/reports/out"
fi
