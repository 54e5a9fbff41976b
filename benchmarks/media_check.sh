#!/usr/bin/env bash
# The GPU evidence for participating media (docs/media.md), run on the GPU machine from the
# repository root after tools/pack_device.sh (which carries .device/, OpenVDB's libraries
# included). Output goes to $OUT (or out/). Steps (STEPS="..." picks some):
#   tests     the media test cases on the GPU (CPU/GPU agreement, analytic cases)
#   scenes    the Breakfast Room with haze and sun shafts, a cloud under sun and sky, the foggy
#             Cornell box: samples/s and per-stage times (medium, shade, shadow, ...)
#   nocost    the Cornell box without media against a baseline binary built before media
#             (BASELINE=path/to/pathtracer, e.g. main's packed to .device/baseline/): the same
#             kernels, so the same time within noise; also with an unused "media" table
#   identity  every scene of scenes/ bit-identical to the baseline's render (needs BASELINE)
#   sass      the machine code of every kernel the baseline has, compared with this build's
#             (cuobjdump -sass; needs BASELINE): scenes without media run these kernels only
#   accuracy  error against time, ratio against delta tracking, on the cloud
set -uo pipefail
OUT="${OUT:-out}"
mkdir -p "$OUT"
ROOT="$PWD"
BIN="$ROOT/.device/bin"
export PT_SOURCE_DIR="$ROOT" PT_BINARY_DIR="$BIN" PT_SHARED_DIR="$ROOT/.device/shared"
[ -e "$ROOT/../shared" ] || ln -s "$ROOT/.device/shared" "$ROOT/../shared"
STEPS="${STEPS:-tests scenes nocost identity sass accuracy}"
R="${REPEATS:-5}"
step() { echo; echo "=== $* ($(date +%T))"; }

if [[ " $STEPS " == *" tests "* ]]; then
  step "media tests with the GPU cases"
  "$BIN/pt_tests" --gtest_filter='Media*' --gtest_brief=1 2>&1 | tee "$OUT/media_tests.log" | tail -20
fi

if [[ " $STEPS " == *" scenes "* ]]; then
  step "media scenes: samples/s and per-stage times (stats JSON per run in $OUT/media_scenes)"
  python3 benchmarks/bench.py --binary "$BIN/pathtracer" --backend cuda --repeats "$R" \
    --scene benchmarks/scenes/breakfast_room_fog.json --scene benchmarks/scenes/cloud_sunsky.json \
    --scene scenes/cornell_fog.json --variants auto:auto --out "$OUT/media_scenes"
  for s in benchmarks/scenes/breakfast_room_fog.json benchmarks/scenes/cloud_sunsky.json \
           scenes/cornell_fog.json; do
    n=$(basename "$s" .json)
    "$BIN/pathtracer" "$s" -o "$OUT/$n.png" --hdr "$OUT/$n.exr" --backend cuda \
      --stats-json "$OUT/$n.stats.json" --quiet
    python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print(sys.argv[2], \
      'Msamples/s', round(s['msamples_per_s'], 3), 'stages ms', s['time_ms']['stages'])" \
      "$OUT/$n.stats.json" "$n"
  done
fi

if [[ " $STEPS " == *" nocost "* ]]; then
  step "the Cornell box: media code must cost nothing"
  # The same scene with a media table nothing uses: no media stage runs.
  python3 - <<'PY' > "$OUT/cornell_unused_media.json"
import re
s = open("scenes/cornell_box.json").read()
s = s[:s.rfind("}")] + ', "media": {"fog": {"type": "homogeneous", "sigma_a": [0, 0, 0], "sigma_s": [1, 1, 1]}}}'
print(s)
PY
  python3 benchmarks/bench.py --binary "$BIN/pathtracer" --backend cuda --repeats "$R" \
    --scene scenes/cornell_box.json --scene "$OUT/cornell_unused_media.json" --variants auto:auto \
    --out "$OUT/nocost_media" -- --spp 256
  if [ -n "${BASELINE:-}" ]; then
    python3 benchmarks/bench.py --binary "$BASELINE" --backend cuda --repeats "$R" \
      --scene scenes/cornell_box.json --variants auto:auto --out "$OUT/nocost_baseline" -- --spp 256
    echo "this build:"; cat "$OUT/nocost_media.md"; echo "baseline:"; cat "$OUT/nocost_baseline.md"
  else
    echo "BASELINE not set: no comparison with a build before media"
  fi
fi

if [[ " $STEPS " == *" identity "* ]]; then
  step "scenes without media: bit-identical to the baseline's GPU render"
  if [ -n "${BASELINE:-}" ]; then
    BACKEND=cuda bash benchmarks/media_identity_check.sh "$BASELINE" "$BIN/pathtracer" \
      "$BIN/image_compare" "$OUT/identity" | grep -E "identical|DIFFERENT"
  else
    echo "BASELINE not set: skipped"
  fi
fi

if [[ " $STEPS " == *" sass "* ]]; then
  step "kernels: the baseline's against this build's machine code"
  if [ -n "${BASELINE:-}" ] && command -v cuobjdump > /dev/null; then
    cuobjdump -sass "$BASELINE" > "$OUT/sass_baseline.txt"
    cuobjdump -sass "$BIN/pathtracer" > "$OUT/sass_media.txt"
    python3 - "$OUT/sass_baseline.txt" "$OUT/sass_media.txt" <<'PY'
import re, sys
def functions(path):
    out, name = {}, None
    for line in open(path):
        m = re.match(r"\s*Function : (\S+)", line)
        if m:
            name = m.group(1); out[name] = []
        elif name and re.search(r"/\*[0-9a-f]{4}\*/", line):
            out[name].append(re.sub(r"/\*[0-9a-f]{4}\*/|;.*", "", line).strip())
    return out
a, b = functions(sys.argv[1]), functions(sys.argv[2])
same = [f for f in a if f in b and a[f] == b[f]]
differ = [f for f in a if f in b and a[f] != b[f]]
gone = [f for f in a if f not in b]
print(f"baseline kernels {len(a)}, this build {len(b)} ({len(b) - len(a)} new: the media kernels)")
print(f"same machine code: {len(same)}; different: {len(differ)}; missing here: {len(gone)}")
for f in differ[:20] + gone[:20]:
    print("  ", f[:160])
PY
  else
    echo "BASELINE not set or no cuobjdump: skipped"
  fi
fi

if [[ " $STEPS " == *" accuracy "* ]]; then
  step "error against time: ratio against delta tracking for shadow rays (cloud under sun and sky)"
  python3 benchmarks/media_accuracy.py --binary "$BIN/pathtracer" --backend cuda \
    --scene benchmarks/scenes/cloud_sunsky.json --size 640x360 --ref-spp "${REF_SPP:-8192}" \
    --seconds "${SECONDS_PER_RUN:-30}" --out "$OUT/media_accuracy"
fi
