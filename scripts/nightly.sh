#!/usr/bin/env bash
# The nightly job in one command: build; the fast tier (every study gets
# results), then the nightly tier (full-size studies overwrite their study's
# folder with tier "full"); the benchmarks and their trend (history appended,
# regressions flagged); the full report (HTML + PDF) over all of it.
# Every step runs even when an earlier one fails; the exit status is non-zero
# if any did. Step wall times and the load average go to
# $BUILD_DIR/results/nightly_steps.csv (shown in the report's provenance), the
# load every minute to nightly_load.csv.
# Env: BUILD_DIR (build), JOBS (nproc), BENCH_REPETITIONS (3), SKIP_BENCHMARKS=1.
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
build="${BUILD_DIR:-$root/build}"
steps="$build/results/nightly_steps.csv"
status=0

step() {  # step NAME COMMAND...: run it, time it, remember a failure
  local name="$1" t0 rc
  shift
  t0=$(date +%s)
  echo "== nightly: $name ($(date -u +%H:%M:%S) UTC, load $(cut -d' ' -f1 /proc/loadavg))"
  "$@"
  rc=$?
  mkdir -p "$(dirname "$steps")"
  echo "$name,$(( $(date +%s) - t0 )),$rc,$(cut -d' ' -f1 /proc/loadavg),$(date -u +%Y-%m-%dT%H:%M:%SZ)" >> "$steps"
  [ "$rc" -eq 0 ] || status=1
  return 0
}

t_start=$(date +%s)
# The studies record the commit built here, not whatever HEAD is when each
# finishes (verification/support/study_io.hpp), and the report expects it.
# Pinned before the build: a commit made while it compiles (19 min under
# load on 2026-12-02) would otherwise label binaries built mostly from the
# one before; a tree that changed during the build is marked dirty.
source_state() { git -C "$root" rev-parse HEAD 2>/dev/null; git -C "$root" status --porcelain --untracked-files=no 2>/dev/null; }
state_before="$(source_state)"
FDEM_SOURCE_COMMIT="$(git -C "$root" rev-parse HEAD 2>/dev/null || true)"
FDEM_SOURCE_DIRTY=0
[ -z "$(git -C "$root" status --porcelain --untracked-files=no 2>/dev/null)" ] || FDEM_SOURCE_DIRTY=1
"$root/scripts/build.sh" || exit 1
if [ "$(source_state)" != "$state_before" ]; then
  echo "== nightly: the source tree changed during the build; results are marked dirty" >&2
  FDEM_SOURCE_DIRTY=1
fi
export FDEM_SOURCE_COMMIT FDEM_SOURCE_DIRTY
expect=()
[ -z "$FDEM_SOURCE_COMMIT" ] || expect=(--expect-commit "$FDEM_SOURCE_COMMIT")
mkdir -p "$build/results"
echo "step,wall_s,exit_code,load_1min_at_end,finished_utc" > "$steps"
# The machine's load every minute while the night runs (the wall times above
# are only readable beside it): $BUILD_DIR/results/nightly_load.csv.
load_log="$build/results/nightly_load.csv"
echo "utc,load_1min,load_5min,load_15min" > "$load_log"
( while :; do echo "$(date -u +%Y-%m-%dT%H:%M:%SZ),$(cut -d' ' -f1-3 /proc/loadavg | tr ' ' ',')" >> "$load_log"
  sleep 60; done ) &
load_sampler=$!
trap 'kill "$load_sampler" 2>/dev/null' EXIT
# The fast tier runs one test per core with one OpenMP thread each; the
# nightly tier runs its studies one at a time on every core.
step fast_tier env OMP_NUM_THREADS=1 ctest --test-dir "$build" --output-on-failure -L 'unit|verification' -LE nightly \
  --parallel "${JOBS:-$(nproc)}"
# The main job's plume (label main; plume_main/), so the nightly report has
# it beside the full plume it is checked against (the main job's channel is
# the full channel shortened, which the nightly tier runs whole).
step main_plume env OMP_NUM_THREADS=1 ctest --test-dir "$build" --output-on-failure -L main -R '^PlumeMain\.'
step nightly_tier ctest --test-dir "$build" --output-on-failure -L nightly
if [ "${SKIP_BENCHMARKS:-0}" != 1 ]; then
  step benchmarks /usr/bin/python3 "$root/benchmarks/trend/run_trend.py" --build-dir "$build" run \
    --repetitions "${BENCH_REPETITIONS:-3}"
  # The report's "DEM against LIGGGHTS" and "The plume's DEM from
  # checkpoints" (results/benchmarks/dem_vs_liggghts.csv,
  # plume_dem_workload.csv); each installs LIGGGHTS from Debian when missing.
  step dem_vs_liggghts /usr/bin/python3 "$root/benchmarks/dem/side_by_side.py" --build-dir "$build" --reps 3
  step plume_dem_workload /usr/bin/python3 "$root/benchmarks/dem/plume_workload.py" --build-dir "$build" \
    --reps 2 --threads 1,2
fi
step trend /usr/bin/python3 "$root/benchmarks/trend/run_trend.py" --build-dir "$build" plot
step report /usr/bin/python3 "$root/reports/generate.py" --results "$build/results" \
  --build-info "$build/build_info.json" --history "$build/results/benchmarks/history.csv" --out "$root/reports/out" \
  "${expect[@]}"
echo "total,$(( $(date +%s) - t_start )),$status,$(cut -d' ' -f1 /proc/loadavg),$(date -u +%Y-%m-%dT%H:%M:%SZ)" >> "$steps"
echo "== nightly: done in $(( $(date +%s) - t_start )) s, status $status; steps in $steps"
exit "$status"
