#!/usr/bin/env bash
# GPU check of the Python module (docs/python.md), run on the GPU machine from the repository
# root. What it needs, packed here beforehand (the device tool carries .device/):
#   bash tools/pack_device.sh        # .device/bin/pathtracer and the Debian libraries it loads
#   bash tools/pack_python.sh        # .device/python/: Debian's python3.11 + stdlib + numpy and
#                                    # build/python/pathtracer*.so (built for CPython 3.11's ABI:
#                                    # the machine's own Python 3.12 cannot import it)
# Or set PY to a CPython 3.11 and PYTHONPATH to a folder holding the module and its lib/.
# Checks (benchmarks/python_check.py): the CUDA image equals the CLI's byte for byte (PFM and
# EXR, 4 scenes; then the same on the CPU), and the cost of a Python call against the CLI for a
# 1-spp 512x512 render. Look for "IDENTICAL" on every line and "python_check: ok"; the overhead
# lines give cli_process_ms, python_process_ms and python_warm_call_ms (a scene loaded once).
# Output in $OUT (or out/): python_check.log, python_check.json, the images compared.
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
if [ -z "${PY:-}" ]; then
  if [ ! -f .device/python/env.sh ]; then
    echo "python_check: no .device/python (run tools/pack_python.sh after the build) and no PY" >&2
    exit 2
  fi
  source .device/python/env.sh
fi
export LD_LIBRARY_PATH="$PWD/.device/bin/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | tee "$OUT/gpu.txt"
"$PY" -c "import sys, pathtracer; print(sys.version.split()[0], pathtracer.__version__, 'cuda:', pathtracer.cuda_available())"
"$PY" benchmarks/python_check.py --cli .device/bin/pathtracer --out "$OUT" "$@" 2>&1 |
  tee "$OUT/python_check.log"
exit "${PIPESTATUS[0]}"
