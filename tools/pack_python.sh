#!/usr/bin/env bash
# Packs the Python module and a Python to run it into .device/python/ for a GPU machine that has
# neither Debian's Python 3.11 nor numpy (the module is built for Debian's CPython 3.11 ABI, so
# the machine's own Python 3.12 cannot load it): Debian's python3.11 binary, its standard library
# (without tests, tkinter, idle and the static libpython), numpy with the BLAS/LAPACK libraries
# it loads, and build/python/pathtracer*.so with the Debian libraries of tools/pack_device.sh.
# About 70 MB unpacked, ~15 MB as .tar.xz. Use it with benchmarks/python_check.sh:
#   source .device/python/env.sh     # sets PYTHONHOME, PYTHONPATH, LD_LIBRARY_PATH, PY
set -euo pipefail
cd "$(dirname "$0")/.."
BUILD="${1:-build}"
DEST=.device/python
MODULE=$(ls "$BUILD"/python/pathtracer*.so)
rm -rf "$DEST" && mkdir -p "$DEST/bin" "$DEST/lib/python3.11" "$DEST/lib/python3/dist-packages" \
                           "$DEST/module/lib"
cp /usr/bin/python3.11 "$DEST/bin/python3"
( cd /usr/lib/python3.11 && tar cf - --exclude='__pycache__' --exclude='test' --exclude='tests' \
    --exclude='idlelib' --exclude='tkinter' --exclude='turtledemo' --exclude='ensurepip' \
    --exclude='config-3.11-*' --exclude='lib2to3' . ) | tar xf - -C "$DEST/lib/python3.11"
( cd /usr/lib/python3/dist-packages && tar cf - --exclude='__pycache__' --exclude='tests' numpy ) \
  | tar xf - -C "$DEST/lib/python3/dist-packages"
# numpy's shared libraries (reference BLAS/LAPACK, libgfortran) beside the module's.
for lib in $(find "$DEST/lib/python3/dist-packages/numpy" -name '*.so' -exec ldd {} + 2>/dev/null |
             awk '/=>/ {print $3}' | sort -u); do
  case "$(basename "$lib")" in
    libc.so*|libm.so*|libpthread*|libdl*|librt*|ld-linux*|libgcc_s*|libstdc++*) ;;
    *) cp -L "$lib" "$DEST/module/lib/" ;;
  esac
done
cp "$MODULE" "$DEST/module/"
# The OpenVDB module, found beside the Python module (src/io/vdb_loader.cpp), and the libraries
# it loads (OpenVDB, TBB, Imath, Blosc, ...) in module/lib.
if [ -f "$BUILD/libpt_vdb.so" ]; then
  cp "$BUILD/libpt_vdb.so" "$DEST/module/"
  for lib in $(ldd "$BUILD/libpt_vdb.so" | awk '/=>/ {print $3}' | sort -u); do
    case "$(basename "$lib")" in
      libc.so*|libm.so*|libpthread*|libdl*|librt*|ld-linux*|libgcc_s*|libstdc++*) ;;
      *) cp -L "$lib" "$DEST/module/lib/" ;;
    esac
  done
fi
for lib in $(ldd "$MODULE" | awk '/=>/ {print $3}' | sort -u); do
  case "$(basename "$lib")" in
    libtiny*|libstb*|libminiz*) cp -L "$lib" "$DEST/module/lib/" ;;
  esac
done
cat > "$DEST/env.sh" <<'ENV'
# source this file: a Python 3.11 with numpy and the pathtracer module, from this folder.
PT_PY_HOME="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
export PYTHONHOME="$PT_PY_HOME" PYTHONPATH="$PT_PY_HOME/module" PYTHONDONTWRITEBYTECODE=1
export LD_LIBRARY_PATH="$PT_PY_HOME/module/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
export PY="$PT_PY_HOME/bin/python3"
ENV
du -sh "$DEST"
