#!/usr/bin/env bash
# Experiment: the pushed group also remembers its second-nearest interior child (taken first
# when the group is popped): pathtracer_second against the committed nearest-first build.
set -uo pipefail
OUT="${OUT:-out}"; mkdir -p "$OUT"
ln -sfn "$PWD/.device/shared" ../shared
exec > >(tee -a "$OUT/run.log") 2>&1
B="$PWD/.device/bin"; S=benchmarks/scenes
python3 $S/make_bunny_field.py > /dev/null
SWEEP="python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $B/pathtracer"
$SWEEP 5 $S/breakfast_room.json,$S/bunny_cornell.json "nearest||" "second|||$B/pathtracer_second" \
  "nearest-perray||--prim-pool off" "second-perray||--prim-pool off|$B/pathtracer_second" | grep -v '^[0-9] '
$SWEEP 5 $S/bunny_field_10k.json "nearest||--spp 64" "second||--spp 64|$B/pathtracer_second" | grep -v '^[0-9] '
for sc in breakfast_room bunny_cornell bunny_field_10k; do
  for v in pathtracer pathtracer_second; do
    "$B/$v" $S/$sc.json -o /tmp/${sc}_$v.exr --width 320 --height 180 --spp 16 --backend cuda --quiet 2>/dev/null
  done
  echo "$sc: $("$B/image_compare" /tmp/${sc}_pathtracer.exr /tmp/${sc}_pathtracer_second.exr 2>&1 | tail -1)"
done
