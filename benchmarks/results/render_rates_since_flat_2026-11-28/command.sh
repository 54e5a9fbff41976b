#!/bin/bash
# One device call (H100, nvidia-h100-x1) on a machine kept warm from a call before, which carried
# d3c2fa2's pathtracer (xz) to build_q/base/pathtracer; this call carried HEAD da50400's pathtracer,
# its libraries and the assets (tools/pack_device.sh, unpacked to build_q/). It ran the loop of
# benchmarks/compare_renders.py written out in the shell (the same runs, order and rounds; that
# script is in this folder's first commit, a0497d0); r.tgz holds every run's stats.
set -u
ln -sfn "$PWD/build_q/shared" ../shared && ln -sfn ../new/lib build_q/base/lib
python3 benchmarks/compare_renders.py --binary base=build_q/base/pathtracer \
  --binary new=build_q/new/pathtracer --rounds 5 --out $OUT/r
