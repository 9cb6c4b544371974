#!/usr/bin/env bash
# Installs the Debian packages fdem needs, only when one is missing. The check
# is one dpkg-query call for the whole list (a few tens of milliseconds), so
# every build can afford it.
set -euo pipefail
packages=(build-essential cmake ninja-build ccache pkg-config
  libeigen3-dev libgsl-dev libyaml-cpp-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev libomp-dev
  zlib1g-dev python3-meshio
  petsc-dev  # PETSc 3.18 (Debian bookworm) with hypre, MUMPS and Open MPI: the fluid's PETSc solve
  python3 python3-matplotlib python3-numpy poppler-utils)
# Prints "name status" for each package dpkg knows; unknown ones go to stderr.
declare -A status=()
while read -r name state; do status[$name]=$state; done < <(
  dpkg-query -W -f='${Package} ${db:Status-Status}\n' "${packages[@]}" 2>/dev/null || true)
missing=()
for p in "${packages[@]}"; do
  [ "${status[$p]:-}" = installed ] || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "install_deps: installing ${missing[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
