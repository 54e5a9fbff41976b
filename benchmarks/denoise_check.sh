#!/usr/bin/env bash
# The denoiser's GPU check (issue 31), run on the GPU machine from the repository root after
# tools/pack_device.sh (the device tool carries .device/). Output goes to $OUT (or out/).
#
# Steps (STEPS picks; default "info tests time quality"):
#   tests    the denoiser's tests with the GPU cases (CPU/GPU agreement among them)
#   time     denoising a 1920x1080 film on the GPU: --denoise's time (first call: buffers,
#            copies) and its kernels alone, five runs; and on 2 CPU cores of this machine
#   quality  relMSE against a REF_SPP reference (default 16384) of ours, per scene of
#            SCENES: 16 spp raw, 16 spp denoised, 256 spp raw (target: 16 denoised < 256 raw)
# A 16k-spp reference takes about 70 s for the bunny at 1080p on an H100 and several minutes
# for the Breakfast Room: one device call per scene, e.g.
#   STEPS="info tests time" bash benchmarks/denoise_check.sh
#   STEPS=quality SCENES=bunny bash benchmarks/denoise_check.sh
#   STEPS=quality SCENES=breakfast REF_SPP=8192 bash benchmarks/denoise_check.sh
#   STEPS=quality SCENES=helmet bash benchmarks/denoise_check.sh
# What to look for: "DENOISE_TIME" lines (GPU kernels <= 20 ms, CPU <= 2 s at 1080p) and
# "DENOISE_QUALITY" lines (denoised16 < raw256 per scene). The reference's own noise is taken
# out of each relMSE (its variance channel / samples; printed as ref_noise).
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
ROOT="$PWD"
BIN="$ROOT/.device/bin"
[ -x "$BIN/pathtracer" ] || BIN="${PT_BUILD:-$ROOT/build}"
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$BIN" PT_SHARED_DIR="$ROOT/.device/shared"
[ -e "$ROOT/../shared" ] || ln -s "$ROOT/.device/shared" "$ROOT/../shared"
STEPS="${STEPS:-info tests time quality}"
SCENES="${SCENES:-bunny breakfast helmet}"
REF_SPP="${REF_SPP:-16384}"
BACKEND="${BACKEND:-cuda}"
PT="$BIN/pathtracer"

step() { echo; echo "=== $* ($(date +%T))"; }

scene_file() {
  case "$1" in
    bunny) echo benchmarks/scenes/bunny_cornell.json ;;
    breakfast) echo benchmarks/scenes/breakfast_room_sunsky.json ;;
    helmet) echo benchmarks/scenes/damaged_helmet.json ;;
    *) echo "$1" ;;
  esac
}

if [[ " $STEPS " == *" info "* ]]; then
  step "device"
  nvidia-smi --query-gpu=name,driver_version,memory.total --format=csv 2>/dev/null || true
  "$PT" --version
fi

if [[ " $STEPS " == *" tests "* ]]; then
  step "denoiser tests, GPU cases included"
  "$BIN/pt_tests" --gtest_brief=1 \
    --gtest_filter='Denoise*:HalfFilms*:FeatureBuffers*:FilmStateExr*:FilmMerge*' 2>&1 |
    tee "$OUT/denoise_tests.log" | tail -15
fi

# The denoiser's stderr line: "pathtracer: denoised on B in S s (passes P ms)".
denoise_times() { sed -n 's/.*denoised on \([a-z]*\) in \([0-9.]*\) s (passes \([0-9.]*\) ms).*/\1 \2 \3/p'; }

if [[ " $STEPS " == *" time "* ]]; then
  step "denoising 1920x1080 (bunny, 1 spp: the render is not what is timed)"
  for run in 1 2 3 4 5; do
    "$PT" benchmarks/scenes/bunny_cornell.json --spp 1 --denoise --backend "$BACKEND" \
      -o "$OUT/time_$run.png" --quiet 2>&1 | denoise_times |
      awk -v r=$run '{printf "DENOISE_TIME gpu run %d: %s total %.1f ms, passes %.1f ms\n", r, $1, $2 * 1000, $3}'
  done
  rm -f "$OUT"/time_*.png
  # Which tile code the CPU denoiser runs here, and whether cores 0 and 1 are one core's two
  # hyperthreads (then "2 cores" are one).
  isa=$(grep -qw avx512f /proc/cpuinfo && echo "AVX-512 code" || echo "x86-64-v3 code")
  siblings=$(cat /sys/devices/system/cpu/cpu0/topology/thread_siblings_list 2>/dev/null)
  echo "-- 2 CPU cores (taskset 0,1; --threads 2; $isa; cpu0's SMT siblings: ${siblings:-?})"
  for run in 1 2; do
    taskset -c 0,1 "$PT" benchmarks/scenes/bunny_cornell.json --spp 1 --denoise --backend cpu \
      --threads 2 -o "$OUT/time_cpu.png" --quiet 2>&1 | denoise_times |
      awk -v r=$run '{printf "DENOISE_TIME cpu2 run %d: total %.1f ms, passes %.1f ms\n", r, $2 * 1000, $3}'
  done
  rm -f "$OUT/time_cpu.png"
fi

if [[ " $STEPS " == *" quality "* ]]; then
  for name in $SCENES; do
    file=$(scene_file "$name")
    step "relMSE on $name ($file), reference $REF_SPP spp"
    dir="$OUT/q_$name"
    mkdir -p "$dir"
    "$PT" "$file" --spp "$REF_SPP" --seed 77 --backend "$BACKEND" -o "$dir/ref.pfm" \
      --hdr "$dir/ref.exr" --stats-json "$dir/ref.json" --quiet 2>&1 | tail -1
    "$PT" "$file" --spp 16 --seed 1 --backend "$BACKEND" --denoise -o "$dir/d16.pfm" \
      --hdr "$dir/d16.exr" --stats-json "$dir/d16.json" --quiet 2>&1 | tail -2
    "$PT" "$file" --spp 256 --seed 2 --backend "$BACKEND" -o "$dir/r256.pfm" \
      --stats-json "$dir/r256.json" --quiet 2>&1 | tail -1
    python3 - "$dir" "$name" <<'EOF'
import json, os, sys
import numpy as np
sys.path.insert(0, "benchmarks")
from accuracy_lib import read_exr, read_pfm
d, name = sys.argv[1], sys.argv[2]
ref = read_exr(os.path.join(d, "ref.exr"))
r = np.stack([ref[c] for c in "RGB"], -1)
# The reference's own noise: the variance of its mean, taken out of every squared error.
noise = np.stack([ref["variance." + c] for c in "RGB"], -1) / np.maximum(ref["samples"], 1)[..., None]
den = r * r + 1e-2
def rel(x):
    return float(np.mean(((x - r) ** 2 - noise) / den))
d16 = read_exr(os.path.join(d, "d16.exr"))
raw16 = np.stack([d16[c] for c in "RGB"], -1)
dn16 = np.stack([d16["denoised." + c] for c in "RGB"], -1)
r256 = read_pfm(os.path.join(d, "r256.pfm"))
t = lambda f: json.load(open(os.path.join(d, f)))["time_ms"]
t16, t256 = t("d16.json"), t("r256.json")
print("DENOISE_QUALITY %s: raw16 %.3e  denoised16 %.3e  raw256 %.3e  ref_noise %.1e  "
      "(16 spp render %.0f ms + denoise %.0f ms; 256 spp render %.0f ms) -> %s"
      % (name, rel(raw16), rel(dn16), rel(r256), float(np.mean(noise / den)),
         t16["render"], t16.get("denoise", 0.0), t256["render"],
         "denoised16 BEATS raw256" if rel(dn16) < rel(r256) else "denoised16 does NOT beat raw256"))
EOF
    rm -f "$dir"/*.pfm "$dir"/*.exr  # the images are large; the stats stay
  done
  (cd "$OUT" && tar czf denoise_quality_stats.tgz q_* && rm -rf q_*)
fi
