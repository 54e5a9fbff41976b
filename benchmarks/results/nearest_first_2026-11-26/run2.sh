#!/usr/bin/env bash
# Nearest interior child first: closest-hit walks only (.device/bin/pathtracer) and also the
# any-hit walks (pathtracer_any, an experimental build), against the session start's
# (pathtracer_base), alternating; the instanced field too; then the images.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn "$PWD/.device/shared" ../shared
exec > >(tee -a "$OUT/run.log") 2>&1
B="$PWD/.device/bin"
SWEEP="python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $B/pathtracer"
S=benchmarks/scenes
python3 $S/make_bunny_field.py > /dev/null
V=("base|||$B/pathtracer_base" "closest||" "closest+any|||$B/pathtracer_any")
$SWEEP 5 $S/breakfast_room.json,$S/bunny_cornell.json,$S/breakfast_room_bunnies.json "${V[@]}"
$SWEEP 5 $S/bunny_field_10k.json "base||--spp 64|$B/pathtracer_base" "closest||--spp 64" \
  "closest+any||--spp 64|$B/pathtracer_any" "base-binary||--spp 64 --bvh binary|$B/pathtracer_base"
$SWEEP 3 ../shared/peer-scenes/pbrt_cornell.json "base||--spp 1024|$B/pathtracer_base" "closest||--spp 1024" \
  "closest+any||--spp 1024|$B/pathtracer_any"
for sc in bunny_field_10k breakfast_room_bunnies; do
  for v in pathtracer_base pathtracer pathtracer_any; do
    $B/$v $S/$sc.json -o /tmp/${sc}_$v.exr --width 320 --height 180 --spp 16 --backend cuda --quiet
  done
  echo "$sc closest: $($B/image_compare /tmp/${sc}_pathtracer_base.exr /tmp/${sc}_pathtracer.exr 2>&1 | tail -1)"
  echo "$sc closest+any: $($B/image_compare /tmp/${sc}_pathtracer_base.exr /tmp/${sc}_pathtracer_any.exr 2>&1 | tail -1)"
done
