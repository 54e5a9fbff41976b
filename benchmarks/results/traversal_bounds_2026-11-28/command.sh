#!/bin/bash
# One device call (H100, nvidia-h100-x1) on a machine kept warm from two calls before, which carried
# the pathtracer of da50400's sources with kTraversalMinBlocks (src/integrator/wavefront.h) = 7 and
# = 6, stripped and xz-ed, to build_q/b7 and build_q/b6; this call carried da50400's own (8), its
# libraries and the assets (tools/pack_device.sh, unpacked to build_q/new). It ran the loop of
# benchmarks/compare_renders.py written out in the shell (the same runs, order and rounds; that
# script is in this folder's first commit, 78896b4); r.tgz holds every run's stats.
set -u
ln -sfn "$PWD/build_q/shared" ../shared
for b in b7 b6; do ln -sfn ../new/lib build_q/$b/lib; done
for b in new b7 b6; do  # registers and stack frame of the traversal kernels
  cuobjdump -res-usage build_q/$b/pathtracer | grep -A1 "Function" | grep -B1 "REG" |
    paste - - | grep "IntersectLayout\|ShadowLayout"
done
python3 benchmarks/compare_renders.py --binary new=build_q/new/pathtracer \
  --binary b7=build_q/b7/pathtracer --binary b6=build_q/b6/pathtracer --rounds 5 --out $OUT/r
