#!/usr/bin/env bash
# A newcomer's first command: install packages, build, render the default scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/install_deps.sh
bash tools/build.sh build
./build/pathtracer scenes/cornell_box.json -o cornell_box.png
echo "Rendered cornell_box.png"
