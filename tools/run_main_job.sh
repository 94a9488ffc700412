#!/usr/bin/env bash
# Installs what is needed, builds everything, and runs the main job: a background
# Blender bake on a default mesh. Writes into ./out (or the folder given as $1).
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
OUT="$(realpath -m "${1:-$MOLDTEX_ROOT/out}")"
moldtex_install_packages
moldtex_build
mkdir -p "$OUT"
blender -b --factory-startup --python-exit-code 1 \
  -P "$MOLDTEX_ROOT/tools/bake_default.py" -- --addon-dir "$MOLDTEX_BUILD/addon" --out "$OUT"
