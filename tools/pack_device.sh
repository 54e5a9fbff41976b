#!/usr/bin/env bash
# Packs what a GPU machine without Debian's libraries needs into .device/ (git-ignored):
# the binaries (RPATH $ORIGIN/lib), the Debian shared libraries they load (with Open MPI's
# runtime in .device/mpi when the build has MPI), and the shared assets the GPU benchmarks read. The device tool carries .device/ along with the tree.
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
rm -rf .device && mkdir -p .device/bin/lib .device/shared/assets .device/shared/peer-scenes
cp "$BUILD/pathtracer" "$BUILD/tests/pt_tests" .device/bin/
for tool in make_mesh_glb make_sky make_vdb instance_bench image_compare; do
  [ -f "$BUILD/$tool" ] && cp "$BUILD/$tool" .device/bin/
done
# The OpenVDB module the binaries load at the first .vdb file (src/io/vdb_loader.cpp).
VDB_MODULE=()
if [ -f "$BUILD/libpt_vdb.so" ]; then
  cp "$BUILD/libpt_vdb.so" .device/bin/
  VDB_MODULE=("$BUILD/libpt_vdb.so")
fi
for lib in $(ldd "$BUILD/pathtracer" "$BUILD/tests/pt_tests" "${VDB_MODULE[@]}" |
             awk '/=>/ {print $3}' | sort -u); do
  # Every Debian library but the C/C++ runtime (the GPU machine's own) and Open MPI's
  # (pack_mpi.sh carries those): glTF, image, Draco, meshopt, WebP, OpenVDB and their needs.
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libgcc_s*|libstdc++*|ld-linux*|libmpi*|libopen-rte*|libopen-pal*) ;;
    libhwloc*|libevent*|libudev*) ;;
    *) cp -L "$lib" .device/bin/lib/ ;;
  esac
done
# A build with MPI carries Debian's Open MPI runtime (relocatable: .device/mpi/env.sh).
if ldd "$BUILD/pathtracer" | grep -q libmpi; then
  bash tools/pack_mpi.sh .device/mpi
fi
# pt_tests also looks for the binaries next to the build tree's layout.
mkdir -p .device/bin/tests && ln -sf ../pt_tests .device/bin/tests/pt_tests
ln -sf lib .device/bin/tests/lib
SHARED=../shared
if [ -d "$SHARED/assets" ]; then
  cp -r "$SHARED/assets/stanford-bunny" "$SHARED/assets/dining-room-bitterli" \
        "$SHARED/assets/bunny-npm" "$SHARED/assets/cornell-box-original" .device/shared/assets/
  rm -rf .device/shared/assets/dining-room-bitterli/reference .device/shared/assets/*/reference
  mkdir -p .device/shared/assets/khronos
  for m in Box Duck GlassHurricaneCandleHolder TransmissionRoughnessTest DamagedHelmet \
           TransmissionTest GlassVaseFlowers; do
    cp -r "$SHARED/assets/khronos/$m" .device/shared/assets/khronos/
  done
  cp "$SHARED/peer-scenes/"* .device/shared/peer-scenes/
  # The published references the accuracy study compares with (EXR only).
  for a in cornell-box-bitterli veach-mis; do
    mkdir -p ".device/shared/assets/$a/reference"
    cp "$SHARED/assets/$a/reference/TungstenRender.exr" ".device/shared/assets/$a/reference/"
    cp "$SHARED/assets/$a/SOURCE.md" ".device/shared/assets/$a/"
  done
fi
du -sh .device
