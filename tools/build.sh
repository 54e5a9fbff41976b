#!/usr/bin/env bash
# Configures and builds into build/ (or $1). Builds the CUDA backend too when nvcc is at
# /usr/local/cuda or on PATH; CUDA stays optional.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD_DIR="${1:-build}"
shift || true
if [ -z "${CUDACXX:-}" ] && [ -x /usr/local/cuda/bin/nvcc ]; then
  export CUDACXX=/usr/local/cuda/bin/nvcc
fi
# PT_CUDA_ARCHITECTURES (CMake's CUDA_ARCHITECTURES list; default 90): CI, which has no GPU,
# sets 90-virtual: the CUDA sources are compiled to PTX only, so compile errors still fail it,
# without ptxas's machine code (half of the longest compile: 7 of 14 minutes on 2 cores).
ARCH_ARGS=()
if [ -n "${PT_CUDA_ARCHITECTURES:-}" ]; then
  ARCH_ARGS=(-DCMAKE_CUDA_ARCHITECTURES="$PT_CUDA_ARCHITECTURES")
fi
cmake -S . -B "$BUILD_DIR" -G Ninja -DCMAKE_BUILD_TYPE=Release "${ARCH_ARGS[@]}" "$@" >/dev/null
cmake --build "$BUILD_DIR" -j"$(nproc)"
