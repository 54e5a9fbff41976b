#!/bin/bash
# Carried: .dev_now/a.tar.xz (HEAD da50400 pathtracer + libs + assets: .dev_now/pack.sh); in two calls before on
# the same warm machine, the binaries of the same sources with kTraversalMinBlocks = 7 and 6
# (src/integrator/wavefront.h), stripped and xz-ed, unpacked to build_q/b7 and build_q/b6.
# Device call D: the traversal kernels' launch bound, 8 blocks of 128 threads per SM (64
# registers, HEAD: new) against 7 (72 registers: b7) and 6 (80: b6), the same sources otherwise;
# 5 interleaved rounds. The binaries of b7 and b6 were carried by two calls before (xz).
set -u
mkdir -p build_q && tar xJf .dev_now/a.tar.xz -C build_q && ln -sfn "$PWD/build_q/shared" ../shared
for b in b7 b6; do ln -sfn ../new/lib build_q/$b/lib; done
nvidia-smi -L
for b in new b7 b6; do echo "== $b"; cuobjdump -res-usage build_q/$b/pathtracer 2>&1 | grep -A1 "Function" | grep -v "^--" | paste - - | grep "IntersectLayout\|ShadowLayout" | sed 's/Function \([^:]*\):.*REG:\([0-9]*\) STACK:\([0-9]*\).*/\2 \3 \1/' | c++filt | sed 's/(unsigned int const\*.*//; s/.*REG//' | awk '{print $1, $2, $NF}' | sed 's/void pt::ParallelForKernelBounded<[0-9]*, pt::WavefrontIntegrator<pt::CudaBackend>:://' ; done
mkdir -p $OUT/r
run() {  # tag binary scene args...
  local tag=$1 b=$2; shift 2
  build_q/$b/pathtracer "$@" --quiet -o /tmp/o.png --stats-json $OUT/r/${tag}_${b}_$i.json 2>/dev/null
}
for i in 1 2 3 4 5; do for b in new b7 b6; do
  run pbrt $b ../shared/peer-scenes/pbrt_cornell.json --spp 1024
  run cb $b scenes/cornell_box.json --width 512 --height 512 --spp 64
  run bunny $b benchmarks/scenes/bunny_cornell.json --spp 1024
  run breakfast $b benchmarks/scenes/breakfast_room.json
done; done
python3 - $OUT/r <<'PY'
import json, sys, glob, statistics as S
d = sys.argv[1]
for scene in ("pbrt", "cb", "bunny", "breakfast"):
    base = None
    for b in ("new", "b7", "b6"):
        runs = [json.load(open(f)) for f in sorted(glob.glob(f"{d}/{scene}_{b}_*.json"))]
        rs = sorted(x["time_ms"]["render"] for x in runs); r = S.median(rs)
        st = {k: S.median(x["time_ms"]["stages"].get(k, 0.0) for x in runs) for k, v in runs[0]["time_ms"]["stages"].items() if not isinstance(v, dict)}
        base = base or r
        print(f"{scene} {b}: render {r:.1f} ms [{rs[0]:.1f}-{rs[-1]:.1f}] ({r / base:.3f}x new) | " +
              " ".join(f"{k} {v:.2f}" for k, v in st.items() if v > 0.3))
PY
cd $OUT && tar czf r.tgz r && rm -rf r
