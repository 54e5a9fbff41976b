#!/bin/bash
# Carried: .dev_now/a.tar.xz (HEAD da50400 pathtracer + libs + assets: .dev_now/pack.sh) and, in a call before on the
# same warm machine, d3c2fa2's binary (xz) unpacked to build_q/base/pathtracer.
# Device call C: render rates of HEAD (.q/new) against d3c2fa2 (.q/base, the flat shade copy,
# before the Sobol sampler and the denoiser's calibration), 5 interleaved rounds: does the
# default path pay for what came since (issue 28's "within 3%")? Also whole-run wall time.
set -u
[ -x build_q/new/pathtracer ] || tar xJf .dev_now/a.tar.xz -C build_q; ln -sfn "$PWD/build_q/shared" ../shared
ls -la build_q/base; ln -sfn ../new/lib build_q/base/lib
nvidia-smi -L; nvidia-smi --query-gpu=driver_version --format=csv,noheader
mkdir -p $OUT/r
run() {  # tag binary scene args...
  local tag=$1 b=$2; shift 2
  local t0=$(date +%s.%N)
  build_q/$b/pathtracer "$@" --quiet -o /tmp/o.png --stats-json $OUT/r/${tag}_${b}_$i.json 2>/dev/null
  local t1=$(date +%s.%N)
  echo "$tag $b $i wall $(python3 -c "print($t1 - $t0)")" >> $OUT/r/wall.txt
}
for i in 1 2 3 4 5; do for b in base new; do
  run pbrt $b ../shared/peer-scenes/pbrt_cornell.json --spp 1024
  run cb $b scenes/cornell_box.json --width 512 --height 512 --spp 64
  run bunny $b benchmarks/scenes/bunny_cornell.json --spp 1024
  run breakfast $b benchmarks/scenes/breakfast_room.json
done; done
python3 - $OUT/r <<'PY'
import json, sys, glob, statistics as S
d = sys.argv[1]
wall = {}
for line in open(f"{d}/wall.txt"):
    tag, b, i, _, w = line.split(); wall.setdefault((tag, b), []).append(float(w))
for scene in ("pbrt", "cb", "bunny", "breakfast"):
    base = None
    for b in ("base", "new"):
        runs = [json.load(open(f)) for f in sorted(glob.glob(f"{d}/{scene}_{b}_*.json"))]
        rs = sorted(x["time_ms"]["render"] for x in runs); r = S.median(rs)
        st = {k: S.median(x["time_ms"]["stages"].get(k, 0.0) for x in runs) for k, v in runs[0]["time_ms"]["stages"].items() if not isinstance(v, dict)}
        base = base or r
        print(f"{scene} {b}: render {r:.1f} ms [{rs[0]:.1f}-{rs[-1]:.1f}] ({r / base:.3f}x base) wall {S.median(wall[(scene, b)]):.3f} s | " +
              " ".join(f"{k} {v:.2f}" for k, v in st.items() if v > 0.3))
PY
cd $OUT && tar czf r.tgz r && rm -rf r
