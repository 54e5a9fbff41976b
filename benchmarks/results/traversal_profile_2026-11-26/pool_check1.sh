set -uo pipefail
ln -sfn $PWD/.device/shared ../shared; P=.device/bin/pathtracer
for sc in benchmarks/scenes/breakfast_room.json benchmarks/scenes/bunny_cornell.json ../shared/peer-scenes/pbrt_cornell.json; do
  for m in 0 1; do PT_EXP_POOL=$m timeout 60 $P $sc -o /tmp/p$m.exr --backend cuda --width 320 --height 180 --spp 16 --quiet 2>&1 | grep -v "effects\|wrote"; done
  echo "$sc: $(.device/bin/image_compare /tmp/p0.exr /tmp/p1.exr | tr '\n' ' ')"
done
PT_EXP_POOL=1 timeout 120 compute-sanitizer --tool memcheck $P benchmarks/scenes/bunny_cornell.json -o /tmp/s.exr --backend cuda --width 96 --height 64 --spp 2 --quiet 2>&1 | grep "ERROR SUMMARY"
PT_EXP_POOL=1 timeout 120 compute-sanitizer --tool racecheck $P benchmarks/scenes/bunny_cornell.json -o /tmp/s.exr --backend cuda --width 96 --height 64 --spp 2 --quiet 2>&1 | grep -i "ERROR SUMMARY\|hazard" | head -5
PT_EXP_POOL=1 timeout 120 compute-sanitizer --tool synccheck $P benchmarks/scenes/bunny_cornell.json -o /tmp/s.exr --backend cuda --width 96 --height 64 --spp 2 --quiet 2>&1 | grep "ERROR SUMMARY"
S=benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json
python3 benchmarks/results/traversal_profile_2026-11-26/envsweep.py $P 3 $S "binary||--bvh binary" "wide||--bvh wide" "pooled|PT_EXP_POOL=1|--bvh wide" 2>&1 | tail -8
