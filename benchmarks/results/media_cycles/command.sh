# Made on the CPU (2 cores) with the media branch's build and Debian's blender 3.4.1:
/usr/bin/python3 benchmarks/media_cycles.py --pathtracer build/pathtracer --make-vdb build/make_vdb \
  --out benchmarks/results/media_cycles
# Only the cloud is here: the fog-filled Cornell box's Cycles render (512 spp) was stopped
# (about 50 minutes on the shared machine). comparison.md was written by media_cycles.py's
# compare() from the cloud's two images.
