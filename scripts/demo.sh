#!/usr/bin/env bash
# Installs, builds, renders the built-in default scene on every configuration and prints where
# the images went and the parity table.
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build=${JANUS_BUILD_DIR:-$root/build}
bash "$root/scripts/build.sh"
"$build/apps/janus/janus" parity --out "$root/out/parity"
