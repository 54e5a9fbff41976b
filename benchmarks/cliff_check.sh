#!/usr/bin/env bash
# The axis-aligned cliff of issue 28: shadow-stage and render times of the sun scenes
# (benchmarks/scenes/sun_*.json: a delta sun straight down, nudged by 1e-7, and along -z) with
# the wide and binary BVH, medians of REPEATS runs, on the backend BACKEND (cpu or cuda).
#   BIN=build/pathtracer BACKEND=cpu REPEATS=3 OUT=out/cliff bash benchmarks/cliff_check.sh
# Prints one line per scene and layout; the --stats-json files land in $OUT.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="${BIN:-build/pathtracer}"
BACKEND="${BACKEND:-cpu}"
REPEATS="${REPEATS:-3}"
OUT="${OUT:-out/cliff}"
EXTRA=()
if [ "$BACKEND" = cpu ]; then EXTRA=(--threads "${THREADS:-1}" --spp "${SPP:-1}"); fi
mkdir -p "$OUT"
for scene in sun_down sun_down_nudged sun_minus_z; do
  for bvh in wide binary; do
    for r in $(seq 1 "$REPEATS"); do
      "$BIN" "benchmarks/scenes/$scene.json" --backend "$BACKEND" --bvh "$bvh" "${EXTRA[@]}" \
        --quiet -o "$OUT/${scene}_${bvh}.png" --stats-json "$OUT/${scene}_${bvh}_$r.json" \
        "${@}" >/dev/null
    done
    python3 - "$OUT" "$scene" "$bvh" "$REPEATS" <<'PY'
import json, statistics, sys
out, scene, bvh, n = sys.argv[1], sys.argv[2], sys.argv[3], int(sys.argv[4])
runs = [json.load(open(f"{out}/{scene}_{bvh}_{r}.json")) for r in range(1, n + 1)]
med = lambda f: statistics.median(f(x) for x in runs)
print(f"{scene:16s} {bvh:6s} shadow {med(lambda x: x['time_ms']['stages']['shadow']):10.1f} ms"
      f"  render {med(lambda x: x['time_ms']['render']):10.1f} ms"
      f"  mean nodes {med(lambda x: x['bvh']['mean_nodes_visited']):8.1f}"
      f"  {med(lambda x: x['mrays_per_s']):8.1f} Mrays/s")
PY
  done
done
