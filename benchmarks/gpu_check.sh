#!/usr/bin/env bash
# The whole GPU check, run on the GPU machine from the repository root after
# tools/pack_device.sh (the device tool carries .device/): build check, GPU test suite,
# CPU/GPU agreement, compute-sanitizer, benchmark matrix. Output goes to $OUT (or out/).
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
ROOT="$PWD"
BIN="$ROOT/.device/bin"
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$BIN" PT_SHARED_DIR="$ROOT/.device/shared"
# Benchmark scenes reach ../../../shared from benchmarks/scenes/: point it at the carried copy.
[ -e "$ROOT/../shared" ] || ln -s "$ROOT/.device/shared" "$ROOT/../shared"
STEPS="${STEPS:-info tests sanitize bench special gltf sort}"  # also: env, serve

step() { echo; echo "=== $* ($(date +%T))"; }

if [[ " $STEPS " == *" info "* ]]; then
  step "device and libraries"
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.sm --format=csv
  ldd "$BIN/pathtracer" | grep -E "not found|tiny|stb" || true
  "$BIN/pathtracer" --version
fi

if [[ " $STEPS " == *" tests "* ]]; then
  step "test suite with the GPU cases enabled"
  "$BIN/pt_tests" --gtest_brief=1 2>&1 | tee "$OUT/gpu_tests.log" | tail -40
fi

if [[ " $STEPS " == *" sanitize "* ]]; then
  step "compute-sanitizer memcheck and racecheck, Cornell box 64x64 4 spp"
  for tool in memcheck racecheck; do
    compute-sanitizer --tool "$tool" --error-exitcode 99 "$BIN/pathtracer" scenes/cornell_box.json \
      -o "$OUT/san_$tool.exr" --width 64 --height 64 --spp 4 --backend cuda --quiet \
      > "$OUT/sanitizer_$tool.log" 2>&1
    echo "$tool: exit $? ($(grep -E 'ERROR SUMMARY|RACECHECK SUMMARY' "$OUT/sanitizer_$tool.log" | tail -1))"
  done
fi

if [[ " $STEPS " == *" bench "* ]]; then
  step "benchmark matrix"
  R="${REPEATS:-5}"
  BENCH="python3 benchmarks/bench.py --binary $BIN/pathtracer --backend cuda --repeats $R"
  # pbrt-v4's own Cornell box at the figure's settings: 512x512, max_depth 8, 1024 spp.
  $BENCH --scene ../shared/peer-scenes/pbrt_cornell.json --out "$OUT/bench_pbrt" -- --spp 1024
  $BENCH --scene benchmarks/scenes/bunny_cornell.json --scene benchmarks/scenes/breakfast_room.json \
    --out "$OUT/bench_scenes"
  # Primary rays alone on the bunny scene.
  $BENCH --scene benchmarks/scenes/bunny_cornell.json --variants on:off,auto:auto \
    --out "$OUT/bench_primary" -- --max-depth 0
fi

if [[ " $STEPS " == *" special "* ]]; then
  step "specialised stage variants against the general one"
  SCENES=""
  for s in scenes/*.json benchmarks/scenes/bunny_cornell.json benchmarks/scenes/breakfast_room.json \
           benchmarks/scenes/breakfast_room_materials.json benchmarks/scenes/duck.json; do
    SCENES="$SCENES --scene $s"
  done
  python3 benchmarks/bench.py --binary "$BIN/pathtracer" --backend cuda --repeats "${REPEATS:-5}" \
    $SCENES --variants "auto:auto:--specialize=on,auto:auto:--specialize=off" \
    --out "$OUT/bench_special" -- --spp 64
fi

if [[ " $STEPS " == *" env "* ]]; then
  step "environment lighting: sun-and-sky scenes, and importance vs uniform vs BSDF-only"
  MAP=benchmarks/scenes/maps/sunsky_2048.exr  # generated, not committed (see env_diffuse.json)
  [ -f "$MAP" ] || { mkdir -p "$(dirname "$MAP")" && "$BIN/make_sky" -o "$MAP" --elevation 35 \
    --azimuth 60 --turbidity 3 --width 2048 --strength 0.03; }
  python3 benchmarks/bench.py --binary "$BIN/pathtracer" --backend cuda --repeats "${REPEATS:-5}" \
    --scene benchmarks/scenes/env_diffuse.json --scene benchmarks/scenes/env_glossy.json \
    --scene benchmarks/scenes/breakfast_room_sunsky.json --out "$OUT/bench_env"
  python3 benchmarks/accuracy_env.py --binary "$BIN/pathtracer" --backend cuda --size 640x480 \
    --spps 16,64,256,1024 --ref-spp 32768 --label "$(nvidia-smi --query-gpu=name \
    --format=csv,noheader | head -1)" --out "$OUT/accuracy_env"
fi

if [[ " $STEPS " == *" gltf "* ]]; then
  step "glTF materials: DamagedHelmet and TransmissionTest at 1080p, full material against legacy"
  python3 benchmarks/gltf_materials_bench.py --binary "$BIN/pathtracer" --backend cuda \
    --repeats "${REPEATS:-3}" --out "$OUT/gltf_materials"
fi

# Not in the default STEPS: STEPS=serve runs it alone (about half a minute).
if [[ " $STEPS " == *" serve "* ]]; then
  step "live preview (--serve): GPU API test, edit-to-frame latency and frame rate at 1080p"
  "$BIN/pt_tests" --gtest_filter='ServeGpu.*:ServeApi.*:ServeInstances.*' --gtest_brief=1 2>&1 | tail -5
  for size in "1920 1080" "512 512"; do
    set -- $size
    python3 benchmarks/serve_latency.py --pathtracer "$BIN/pathtracer" --backend cuda \
      --scene scenes/cornell_box.json --width "$1" --height "$2" --edits 30 --seconds 5 \
      --json "$OUT/serve_cornell_$1x$2.json"
  done
  python3 benchmarks/serve_latency.py --pathtracer "$BIN/pathtracer" --backend cuda \
    --scene benchmarks/scenes/bunny_cornell.json --width 1920 --height 1080 --edits 30 \
    --seconds 5 --json "$OUT/serve_bunny_1920x1080.json"
fi

if [[ " $STEPS " == *" sort "* ]]; then
  step "shading order (issue 11): scenes x compaction x --sort x --sort-method, medians of 5"
  python3 benchmarks/sort_bench.py --binary "$BIN/pathtracer" --backend cuda \
    --repeats "${REPEATS:-5}" --out "$OUT/sort"
fi
