#!/usr/bin/env bash
# GPU check of the live preview (issue 33), run on the GPU machine from the repository root
# after `bash tools/pack_device.sh` (.device/bin/pathtracer and its libraries).
# 1. The preview's GPU tests (ServeGpu*: edits, coarse frames on the CUDA session).
# 2. benchmarks/serve_latency.py on the CUDA backend, Cornell box at 512^2: a continuous 30 Hz
#    orbit for 4 s (frames shown per second during it, by kind), then 30 single camera edits
#    (edit -> first frame, client and server), then the steady frame rate. Targets: orbit
#    >= 20 frames/s shown, edit -> frame <= 50 ms (median). The same at 1920x1080 for scale,
#    and at 1920x1080 with the page's denoise on (--denoise: "denoise_ms", frames/s).
# Look for "orbit_frames_per_s" and "edit_to_frame_ms_median" in $OUT/serve_check_*.json and
# the summary lines in $OUT/serve_check.log; the script prints PASS/MISS against the targets.
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
BIN="${BIN:-.device/bin/pathtracer}"
TESTS="${TESTS:-.device/bin/tests/pt_tests}"
export LD_LIBRARY_PATH="$PWD/.device/bin/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
nvidia-smi --query-gpu=name,driver_version --format=csv,noheader 2>/dev/null | tee "$OUT/gpu.txt"
status=0
{
  "$TESTS" --gtest_filter='ServeGpu*:ServeState.ACoarse*:DenoiseServe*' || status=1
  for size in "512 512" "1920 1080"; do
    set -- $size
    python3 benchmarks/serve_latency.py --pathtracer "$BIN" --scene scenes/cornell_box.json \
      --backend cuda --width "$1" --height "$2" --orbit-seconds 4 --edits 30 --seconds 3 \
      --json "$OUT/serve_check_${1}x${2}.json" || status=1
  done
  # The page's denoise toggle on (--serve --denoise): steady frames shown through the GPU's
  # denoiser; informational (no target), look at "denoise_ms" and frames/s.
  python3 benchmarks/serve_latency.py --pathtracer "$BIN" --scene scenes/cornell_box.json \
    --backend cuda --width 1920 --height 1080 --edits 10 --seconds 3 --denoise \
    --json "$OUT/serve_check_denoise_1920x1080.json" || status=1
  python3 - "$OUT/serve_check_512x512.json" <<'PY' || status=1
import json, sys
r = json.load(open(sys.argv[1]))
fps, ms = r.get("orbit_frames_per_s", 0), r["edit_to_frame_ms_median"]
print(f"orbit {fps:.1f} frames/s (target >= 20): {'PASS' if fps >= 20 else 'MISS'}")
print(f"edit -> frame {ms:.1f} ms median (target <= 50): {'PASS' if ms <= 50 else 'MISS'}")
sys.exit(0 if fps >= 20 and ms <= 50 else 1)
PY
  exit $status
} 2>&1 | tee "$OUT/serve_check.log"
exit "${PIPESTATUS[0]}"
