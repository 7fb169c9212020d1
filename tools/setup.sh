#!/usr/bin/env bash
# One command on a fresh Debian 12: install what is missing, build, and run
# the main job (render the built-in scene: no file needed).
set -euo pipefail
cd "$(dirname "$0")/.."
tools/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build
./build/raplas render --out render.png --json render.json
