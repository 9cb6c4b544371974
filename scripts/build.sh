#!/usr/bin/env bash
# Configure and build fdem into BUILD_DIR (default build/). Extra args go to cmake.
# validate.sh and test.sh both build through here with the same flags
# (warnings are errors), so whichever runs second finds the build up to date.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
"$root/scripts/install_deps.sh"
build="${BUILD_DIR:-$root/build}"
# Paths relative to the checkout, so a fresh clone elsewhere reuses the compiler cache.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE="${BUILD_TYPE:-Release}" -DFDEM_WERROR=ON "$@"
cmake --build "$build" --parallel "${JOBS:-$(nproc)}"
