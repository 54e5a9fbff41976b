#!/usr/bin/env bash
# Installs every Debian package the build, the tests and the benchmark plots need.
set -euo pipefail
SUDO=""
[ "$(id -u)" -ne 0 ] && SUDO="sudo"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends \
  build-essential cmake ninja-build pkg-config git python3 python3-matplotlib python3-numpy \
  libglm-dev nlohmann-json3-dev libtinygltf-dev libtinyobjloader-dev libstb-dev \
  libtinyexr-dev libgtest-dev clang-14 libclang-rt-14-dev libopenmpi-dev openmpi-bin \
  libcpp-httplib-dev chromium libdraco-dev libmeshoptimizer-dev libwebp-dev zlib1g-dev \
  pybind11-dev python3-dev python3-pytest >/dev/null
# Grid media from .vdb files (optional at configure time; src/io/vdb_io.cpp).
$SUDO apt-get install -y -qq --no-install-recommends libopenvdb-dev >/dev/null
echo "install_deps: Debian packages installed"
