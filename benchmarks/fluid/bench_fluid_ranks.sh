#!/usr/bin/env bash
# The fluid step on 1 and 2 MPI ranks, side by side: `fdem run` of a
# fluid-only box (inlet at x_min, outlet at x_max, 5 tetrahedra per cell)
# with PETSc's solve on 1 rank, then `mpirun -n 2`, interleaved REPS times.
# Prints each run's fluid seconds (fdem run's end-of-run line) and the
# ratio 1 rank / 2 ranks of the medians (the speed-up), with the load.
# Usage: benchmarks/fluid/bench_fluid_ranks.sh [BUILD_DIR] [CELLS_PER_AXIS] [STEPS] [REPS]
set -euo pipefail
build="${1:-build}"
n="${2:-27}"        # 27^3 cells = 98415 tetrahedra
steps="${3:-4}"
reps="${4:-2}"
fdem="$(cd "$build" && pwd)/solver/app/fdem"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
size=$(python3 -c "print($n * 0.01)")
cat > "$work/box.yaml" <<YAML
title: fluid step cost on MPI ranks ($n^3 cells)
effects: {fluid: true}
domain: {lower: [0, 0, 0], upper: [$size, $size, $size]}
mesh: {cells: [$n, $n, $n]}
fluid:
  density: 1000
  viscosity: 1.0e-3
  boundaries:
    x_min: {type: inlet, velocity: [0.05, 0, 0]}
    x_max: outlet
  solver: {linear_solver: petsc}
time: {fluid_step: 1.0e-2, end: $(python3 -c "print($steps * 0.01)")}
output: {directory: out}
YAML
fluid_seconds() { sed -n 's/.*fdem run: wall [^:]*: fluid \([0-9.e+-]*\) s.*/\1/p' "$1"; }
one=() two=()
for r in $(seq "$reps"); do
  OMP_NUM_THREADS=1 "$fdem" run "$work/box.yaml" -o "$work/one$r" -q -t 1 2> "$work/one$r.log"
  one+=("$(fluid_seconds "$work/one$r.log")")
  OMP_NUM_THREADS=1 mpirun --allow-run-as-root --oversubscribe -n 2 "$fdem" run "$work/box.yaml" -o "$work/two$r" -q \
    2> "$work/two$r.log"
  two+=("$(fluid_seconds "$work/two$r.log")")
  echo "rep $r: fluid ${one[-1]} s on 1 rank, ${two[-1]} s on 2 ranks; load $(cut -d' ' -f1-3 /proc/loadavg)"
done
python3 - "${one[*]}" "${two[*]}" "$n" "$steps" <<'PY'
import statistics, sys
one = [float(x) for x in sys.argv[1].split()]; two = [float(x) for x in sys.argv[2].split()]
n, steps = int(sys.argv[3]), int(sys.argv[4])
print(f"{5 * n**3} tetrahedra, {steps} fluid steps: median fluid {statistics.median(one):.3g} s (1 rank) / "
      f"{statistics.median(two):.3g} s (2 ranks) = speed-up {statistics.median(one) / statistics.median(two):.2f}")
PY
