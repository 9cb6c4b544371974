#!/usr/bin/env bash
# Configures fdem with FDEM_BUILD_TESTS/BENCHMARKS/REPORT off and GoogleTest,
# Google Benchmark and Python made unfindable (CMAKE_DISABLE_FIND_PACKAGE_*:
# a find_package(... REQUIRED) of them fails the configure), then checks the
# build would make fdem and no test or benchmark executable.
# Usage: check_solver_alone.sh SOURCE_DIR SCRATCH_BUILD_DIR
set -euo pipefail
source_dir=$1 build=$2
rm -rf "$build"
cmake -S "$source_dir" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DFDEM_BUILD_TESTS=OFF -DFDEM_BUILD_BENCHMARKS=OFF -DFDEM_BUILD_REPORT=OFF \
  -DCMAKE_DISABLE_FIND_PACKAGE_GTest=ON -DCMAKE_DISABLE_FIND_PACKAGE_benchmark=ON \
  -DCMAKE_DISABLE_FIND_PACKAGE_Python3=ON >"$build.log" 2>&1 || { cat "$build.log"; exit 1; }
targets=$(ninja -C "$build" -t targets all | sed -n 's/^\([A-Za-z0-9_]*\): phony$/\1/p')
rm -rf "$build" "$build.log"
echo "phony targets: $(echo $targets)"
grep -qx fdem <<<"$targets" || { echo "FAIL: no fdem target"; exit 1; }
if grep -E '^(test_|verify_|bench_)' <<<"$targets"; then
  echo "FAIL: test or benchmark targets configured with every FDEM_BUILD_* off"
  exit 1
fi
echo "ok: the solver configures alone"
