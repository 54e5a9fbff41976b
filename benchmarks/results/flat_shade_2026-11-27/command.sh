#!/bin/bash
# One device call (H100, nvidia-h100-x1); .q/ held the binaries: base = bc3982d, new0 = 5ebfca7,
# flat = the merge of dnfast on the flat shade copy (this folder's commit).
# Original note:: (1) pbrt-v4's box and the 512^2 Cornell box: BASE (bc3982d), NEW0
# (5ebfca7), FLAT (HEAD: flat shade copy + tiled CPU denoiser), 7 interleaved rounds; (2) the
# denoiser's time (FLAT), and the CPU denoiser NEW0 against FLAT on 2 cores, interleaved.
set -u
mkdir -p .q && tar xJf .dev_now/q28.tar.xz -C .q && ln -sfn "$PWD/.q/shared" ../shared
nvidia-smi -L; lscpu | grep -E "Model name|^CPU\(s\)|Thread" ; cat /sys/devices/system/cpu/cpu0/topology/thread_siblings_list
mkdir -p $OUT/p
for i in 1 2 3 4 5 6 7; do for b in base new0 flat; do
  .q/$b/pathtracer .dev_now/pbrt_cornell.json --spp 1024 --quiet -o /tmp/p.png --stats-json $OUT/p/pbrt_${b}_$i.json 2>/dev/null
  .q/$b/pathtracer scenes/cornell_box.json --width 512 --height 512 --spp 64 --quiet -o /tmp/p.png --stats-json $OUT/p/cb_${b}_$i.json 2>/dev/null
done; done
python3 - $OUT/p <<'PY'
import json, sys, glob, statistics as S
d = sys.argv[1]
for scene in ("pbrt", "cb"):
    base = None
    for b in ("base", "new0", "flat"):
        runs = [json.load(open(f)) for f in sorted(glob.glob(f"{d}/{scene}_{b}_*.json"))]
        med = lambda f: S.median(f(x) for x in runs)
        r = med(lambda x: x["time_ms"]["render"])
        rs = sorted(x["time_ms"]["render"] for x in runs)
        st = {k: med(lambda x: x["time_ms"]["stages"].get(k, 0.0)) for k, v in runs[0]["time_ms"]["stages"].items() if not isinstance(v, dict)}
        base = base or r
        print(f"{scene} {b}: render {r:.1f} ms [{rs[0]:.1f}-{rs[-1]:.1f}] ({r / base:.3f}x base; {runs[0]['samples'] / r / 1e3:.1f} M samples/s) | " +
              " ".join(f"{k} {v:.2f}" for k, v in st.items() if v > 0.3))
PY
cd $OUT && tar czf p.tgz p && rm -rf p && cd - >/dev/null
PT_BUILD=$PWD/.q/flat STEPS=time bash benchmarks/denoise_check.sh 2>&1 | grep -E "DENOISE_TIME|^-- "
echo "-- CPU denoiser, 2 logical CPUs 0,1, NEW0 (whole-image passes) / FLAT (tiles), interleaved"
for run in 1 2 3; do for b in new0 flat; do
  echo -n "$b: "; taskset -c 0,1 .q/$b/pathtracer benchmarks/scenes/bunny_cornell.json --spp 1 --denoise --backend cpu --threads 2 -o /tmp/t.png --quiet 2>&1 | grep denoised
done; done
other=$(awk -F, '{print $NF}' /sys/devices/system/cpu/cpu0/topology/thread_siblings_list | tr -d ' ')
echo "-- 2 physical cores (CPUs 0 and 2, if 0's sibling is $other)"
for run in 1 2 3; do for b in new0 flat; do
  echo -n "$b: "; taskset -c 0,2 .q/$b/pathtracer benchmarks/scenes/bunny_cornell.json --spp 1 --denoise --backend cpu --threads 2 -o /tmp/t.png --quiet 2>&1 | grep denoised
done; done
