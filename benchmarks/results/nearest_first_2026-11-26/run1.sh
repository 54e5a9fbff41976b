#!/usr/bin/env bash
# Nearest interior child first in the wide closest-hit walk: this build (.device/bin/pathtracer)
# against the session start's (.device/bin/pathtracer_base), alternating, then the images.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn "$PWD/.device/shared" ../shared
exec > >(tee -a "$OUT/run.log") 2>&1
B="$PWD/.device/bin"
SWEEP="python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $B/pathtracer"
S=benchmarks/scenes
$SWEEP 5 $S/breakfast_room.json,$S/bunny_cornell.json,$S/breakfast_room_bunnies.json \
  "base|||$B/pathtracer_base" "nearest||" "base-perray||--prim-pool off|$B/pathtracer_base" \
  "nearest-perray||--prim-pool off"
$SWEEP 3 ../shared/peer-scenes/pbrt_cornell.json "base||--spp 1024|$B/pathtracer_base" "nearest||--spp 1024"
for sc in breakfast_room bunny_cornell; do
  for pp in on off; do
    for v in pathtracer_base pathtracer; do
      $B/$v $S/$sc.json -o /tmp/${sc}_${pp}_$v.exr --width 320 --height 180 --spp 16 --backend cuda \
        --prim-pool $pp --quiet
    done
    echo "$sc pool $pp: $($B/image_compare /tmp/${sc}_${pp}_pathtracer_base.exr /tmp/${sc}_${pp}_pathtracer.exr 2>&1 | tail -1)"
  done
done
