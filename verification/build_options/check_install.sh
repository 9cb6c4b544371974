#!/usr/bin/env bash
# Installs a built tree into a scratch prefix and checks what lands there:
# bin/fdem, the scene documentation and the sample scenes; the installed
# fdem prints the schema and checks an installed sample scene.
# Usage: check_install.sh BUILD_DIR SCRATCH_PREFIX
set -euo pipefail
build=$1 prefix=$2
rm -rf "$prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
fail() { echo "FAIL: $*"; rm -rf "$prefix"; exit 1; }
[ -x "$prefix/bin/fdem" ] || fail "no $prefix/bin/fdem"
docs="$prefix/share/doc/fdem"
grep -q '^## Schema' "$docs/scene-files.md" || fail "no scene documentation in $docs/scene-files.md"
[ -f "$docs/examples/dry_drop.yaml" ] || fail "no sample scenes in $docs/examples"
# Captured first: grep -q closing the pipe early would SIGPIPE fdem, which pipefail reports.
schema=$("$prefix/bin/fdem" help scene) || fail "installed fdem help scene failed"
grep -qx 'contact.kn  (number > 0; default: required with particles and normal contact)' <<<"$schema" \
  || fail "installed fdem help scene does not print contact.kn"
"$prefix/bin/fdem" check "$docs/examples/dry_drop.yaml" >/dev/null || fail "installed fdem check of dry_drop.yaml"
rm -rf "$prefix"
echo "ok: fdem and the scene documentation install and run"
