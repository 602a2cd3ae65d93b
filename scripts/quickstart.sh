#!/usr/bin/env bash
# README command 1: install, build (release preset) and render the built-in default scene to sphere.png.
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/install-deps.sh
cmake --preset release >/dev/null
cmake --build --preset release --target prism
./build/release/apps/prism render --scene builtin:sphere --width 1280 --height 720 --out sphere.png "$@"
