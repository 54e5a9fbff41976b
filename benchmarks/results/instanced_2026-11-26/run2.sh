# Flat scenes, wide layout, three binaries alternating: head (e7b450a), A (11a3611: the walk
# written with WideWalk) and B (A with one primitive per loop iteration instead of a node's
# primitives all at once: an experiment). Medians of 5.
set -uo pipefail
ln -sfn $PWD/.device/shared ../shared
B=$PWD/.device/bin; SW=benchmarks/results/traversal_profile_2026-11-26/envsweep.py
nvidia-smi --query-gpu=name --format=csv,noheader
python3 $SW $B/pathtracer 5 benchmarks/scenes/breakfast_room.json,benchmarks/scenes/bunny_cornell.json "head||--bvh wide|$B/pathtracer_head" "A||--bvh wide|$B/pathtracer_a" "B||--bvh wide" "head-perray||--bvh wide --prim-pool off|$B/pathtracer_head" "A-perray||--bvh wide --prim-pool off|$B/pathtracer_a" "B-perray||--bvh wide --prim-pool off" 2>&1 | tail -14
python3 $SW $B/pathtracer 5 ../shared/peer-scenes/pbrt_cornell.json "head||--bvh wide --spp 1024|$B/pathtracer_head" "A||--bvh wide --spp 1024|$B/pathtracer_a" "B||--bvh wide --spp 1024" 2>&1 | tail -5
