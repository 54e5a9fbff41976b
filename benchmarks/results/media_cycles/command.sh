# Made on the CPU (2 cores) with Debian's blender 3.4.1.
# The cloud (media branch's build, 160x160, 512 spp each):
/usr/bin/python3 benchmarks/media_cycles.py --pathtracer build/pathtracer --make-vdb build/make_vdb \
  --out benchmarks/results/media_cycles
# The fog-filled Cornell box (main at 7ac1e06's build, 2026-11-27; smaller than the cloud so that
# Cycles finishes on the shared machine: 128x128, ours 1024 spp, Cycles 256 spp; the cloud's
# files were already there, so only the Cornell box was rendered):
/usr/bin/python3 benchmarks/media_cycles.py --pathtracer build/pathtracer --make-vdb build/make_vdb \
  --out benchmarks/results/media_cycles --size 128 --spp 1024 --cycles-spp 256
# comparison.md is written by media_cycles.py's compare() from each pair of images.
