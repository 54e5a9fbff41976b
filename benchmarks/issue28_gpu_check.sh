#!/usr/bin/env bash
# Issue 28 on one GPU, the build before (BASE) against this branch's (NEW), in one call:
#  1. NEW's tests with the GPU cases (AxisRays, Lbvh, BvhWide, every *Gpu* case);
#     regress: the Cornell box's render and traversal stages, both layouts, both builds (the
#     parallel-axis cull must cost rays without a parallel axis nothing), and the registers of
#     each build's kernels (cuobjdump, where the toolkit has it);
#  2. the axis-aligned cliff: shadow-stage ms of the sun scenes, wide and binary, both builds;
#  3. the wall clock of whole runs (bunny 1080p 1024 spp, Breakfast Room, the 3.3M scene):
#     the process's wall time, NEW's time_ms parts, render rates (no regression);
#  4. BVH builds: SAH against the GPU's linear BVH on the 3.3M scene (build ms, SAH cost,
#     rays/s), and command to finished 64-spp image on the 10M scene (BASE sah, NEW auto).
# Medians of REPEATS (5). Packing, on the build machine (CUDA build of this branch in build/,
# the base's, e.g. main before the merge of this branch, in BASE_BUILD):
#   tools/pack_device.sh build && mkdir -p .device/base && cp "$BASE_BUILD/pathtracer" \
#     .device/base/ && ln -sfn ../bin/lib .device/base/lib
# then on the GPU machine, from the repository root:
#   BASE=.device/base NEW=.device/bin SHARED=.device/shared OUT=$OUT \
#     bash benchmarks/issue28_gpu_check.sh
# What to look for: tests pass; cliff: NEW's wide shadow ms close to binary's and to the
# nudged scene's; wall: NEW's wall time - render <= 0.3 s on the bunny (issue 28's target) and
# its time_ms parts summing to within 2% of the wall; bvh: the gpu builder's bvh_build <= 50 ms
# on the 3.3M scene with Mrays/s >= 90% of sah's, built_on "device"; the 10M scene's wall time
# BASE / NEW >= 3. The 2-GPU whole-run table: benchmarks/mpi_gpu_check.sh with NEW's pack on
# nvidia-h100-x2 (efficiency = T1 / (2 T2) from the wall times it prints).
# Benchmark scenes reach ../../../shared from benchmarks/scenes/: it must lead to SHARED.
set -uo pipefail
BASE="${BASE:?BASE: the folder of the base build (pathtracer)}"
NEW="${NEW:?NEW: the folder of this build (pathtracer, pt_tests)}"
SHARED="${SHARED:?SHARED: the parent of the assets folder}"
OUT="${OUT:-out}"
REPEATS="${REPEATS:-5}"
STEPS="${STEPS:-tests regress cliff wall bvh}"
mkdir -p "$OUT/stats"
exec > >(tee "$OUT/log.txt") 2>&1
[ -e ../shared ] || ln -s "$SHARED" ../shared
T="$(mktemp -d)"
step() { echo; echo "=== $* ($(date +%T))"; }
nvidia-smi -L; nproc

# wall BIN NAME ARGS...: REPEATS runs; prints the median wall seconds; keeps the stats.
wall() {
  local bin="$1" name="$2"; shift 2
  local times=()
  for r in $(seq 1 "$REPEATS"); do
    local t0; t0=$(date +%s%N)
    "$bin/pathtracer" "$@" --quiet -o "$T/$name.png" --stats-json "$OUT/stats/${name}_$r.json" \
      >"$T/$name.log" 2>&1 || { echo "$name: failed"; tail -3 "$T/$name.log"; }
    local t1; t1=$(date +%s%N)
    times+=($(( (t1 - t0) / 1000000 )))
  done
  printf '%s\n' "${times[@]}" | sort -n | awk -v n="$name" '{a[NR]=$1/1000} END {printf "%-28s wall %.3f s (min %.3f max %.3f)\n", n, a[int((NR+1)/2)], a[1], a[NR]}'
}

# summary NAME: medians of the stats of wall's runs: parts, render, rates, build.
summary() {
  python3 - "$OUT/stats" "$1" "$REPEATS" <<'PY'
import json, statistics, sys
d, name, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = [json.load(open(f"{d}/{name}_{r}.json")) for r in range(1, n + 1)]
med = lambda f: statistics.median(f(x) for x in runs)
t = runs[0]["time_ms"]
line = (f"  {name}: total {med(lambda x: x['time_ms']['total']):.1f} ms, render "
        f"{med(lambda x: x['time_ms']['render']):.1f}, load {med(lambda x: x['time_ms']['load']):.1f}, "
        f"bvh {med(lambda x: x['time_ms']['bvh_build']):.1f}, {med(lambda x: x['mrays_per_s']):.1f} Mrays/s, "
        f"sah {runs[0]['bvh']['sah_cost']:.2f}, shadow {med(lambda x: x['time_ms']['stages']['shadow']):.1f}, "
        f"builder {runs[0]['bvh'].get('builder', '-')} on {runs[0]['bvh'].get('built_on', '-')}")
print(line)
if "parts" in t:
    print("    parts: " + ", ".join(f"{p} {med(lambda x: x['time_ms'][p]):.1f}" for p in t["parts"]))
    print(f"    first pixel {med(lambda x: x['time_ms']['first_pixel'] or 0):.1f} ms, background "
          f"{runs[0]['time_ms']['background']}")
PY
}

if [[ " $STEPS " == *" tests "* ]]; then
  step "NEW's tests with the GPU cases"
  (cd "$NEW" && timeout "${TEST_SECONDS:-180}" ./pt_tests --gtest_brief=1 \
     --gtest_filter="${TEST_FILTER:-AxisRays*:Lbvh*:*Gpu*:RunTimeline*}" ) > "$OUT/tests.log" 2>&1
  echo "pt_tests: exit $?"; tail -4 "$OUT/tests.log"
fi

if [[ " $STEPS " == *" regress "* ]]; then
  step "the Cornell box, no parallel rays (512x512, 64 spp): render and traversal stages"
  for bvh in wide binary; do
    for b in BASE NEW; do
      bin=$([ $b = BASE ] && echo "$BASE" || echo "$NEW")
      wall "$bin" "regress_${bvh}_$b" scenes/cornell_box.json --bvh "$bvh" --width 512 \
        --height 512 --spp 64 >/dev/null
      summary "regress_${bvh}_$b" | head -1
      python3 - "$OUT/stats" "regress_${bvh}_$b" "$REPEATS" <<'PY'
import json, statistics, sys
d, name, n = sys.argv[1], sys.argv[2], int(sys.argv[3])
runs = [json.load(open(f"{d}/{name}_{r}.json")) for r in range(1, n + 1)]
st = lambda k: statistics.median(x["time_ms"]["stages"][k] for x in runs)
print(f"    intersect {st('intersect'):.2f} ms, shadow {st('shadow'):.2f} ms, shade {st('shade'):.2f} ms")
PY
    done
  done
  if command -v cuobjdump >/dev/null || [ -x /usr/local/cuda/bin/cuobjdump ]; then
    CUOBJ=$(command -v cuobjdump || echo /usr/local/cuda/bin/cuobjdump)
    for b in BASE NEW; do
      bin=$([ $b = BASE ] && echo "$BASE" || echo "$NEW")
      "$CUOBJ" -res-usage "$bin/pathtracer" 2>/dev/null | grep -A1 "Function" | paste - - |
        grep -iE "intersect|shadow|occlu|trace" | sed -E 's/.*Function ([^ :]*).*REG:([0-9]+).*STACK:([0-9]+).*/\1 REG \2 STACK \3/' |
        cut -c1-160 > "$OUT/regs_$b.txt"
      echo "$b: $(wc -l < "$OUT/regs_$b.txt") traversal kernels; registers:"; head -12 "$OUT/regs_$b.txt"
    done
  fi
fi

if [[ " $STEPS " == *" cliff "* ]]; then
  step "the axis-aligned cliff (shadow stage ms, 640x360, 16 spp)"
  for scene in sun_down sun_down_nudged sun_minus_z; do
    for bvh in wide binary; do
      for b in BASE NEW; do
        bin=$([ $b = BASE ] && echo "$BASE" || echo "$NEW")
        wall "$bin" "cliff_${scene}_${bvh}_$b" "benchmarks/scenes/$scene.json" --bvh "$bvh" \
          --width 640 --height 360 --spp 16 >/dev/null
        summary "cliff_${scene}_${bvh}_$b" | head -1
      done
    done
  done
fi

if [[ " $STEPS " == *" wall "* ]]; then
  step "whole runs: wall time and its parts"
  for spec in "bunny:benchmarks/scenes/bunny_cornell.json:--spp 1024" \
              "breakfast:benchmarks/scenes/breakfast_room.json:" \
              "big3m:benchmarks/scenes/breakfast_room_bunnies.json:--spp 16"; do
    IFS=: read -r name scene args <<<"$spec"
    # WALL_VARIANTS may add EAGER: NEW with every kernel loaded at start-up (no warm-up wave).
    for b in ${WALL_VARIANTS:-BASE NEW}; do
      bin=$([ $b = BASE ] && echo "$BASE" || echo "$NEW")
      # shellcheck disable=SC2086
      if [ "$b" = EAGER ]; then CUDA_MODULE_LOADING=EAGER wall "$bin" "wall_${name}_$b" "$scene" $args
      else wall "$bin" "wall_${name}_$b" "$scene" $args; fi
      summary "wall_${name}_$b"
    done
  done
fi

if [[ " $STEPS " == *" bvh "* ]]; then
  step "BVH builds: SAH against the GPU's linear BVH (NEW), 3.3M triangles"
  for builder in sah gpu; do
    wall "$NEW" "bvh_big3m_$builder" benchmarks/scenes/breakfast_room_bunnies.json --spp 16 \
      --bvh-build "$builder"
    summary "bvh_big3m_$builder"
  done
  step "the 10M scene, command to finished 64-spp image"
  python3 benchmarks/scenes/make_large_scene.py --bunnies 141 --out "$T/big10m.json" >/dev/null
  REPEATS="${BIG_REPEATS:-3}" wall "$BASE" big10m_BASE "$T/big10m.json" --spp 64
  REPEATS="${BIG_REPEATS:-3}" summary big10m_BASE
  REPEATS="${BIG_REPEATS:-3}" wall "$NEW" big10m_NEW "$T/big10m.json" --spp 64
  REPEATS="${BIG_REPEATS:-3}" summary big10m_NEW
fi
tar czf "$OUT/stats.tar.gz" -C "$OUT" stats && rm -rf "$OUT/stats"
