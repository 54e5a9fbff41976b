#!/usr/bin/env bash
# The test command: build (with CUDA when a toolkit is present) and run the whole suite.
# GPU cases skip on a machine without a GPU and run for real on one.
set -euo pipefail
cd "$(dirname "$0")/.."
bash tools/build.sh build
cd build && ctest -j"$(nproc)" --output-on-failure --timeout 900
