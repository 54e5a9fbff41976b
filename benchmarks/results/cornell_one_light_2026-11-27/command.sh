# H100 (nvidia-h100-x1), main 228b6cd's parent tree (the light BVH's one-light tree, 4a0467b,
# merged), packed with tools/pack_device.sh. The Cornell box with bvh against power, as
# benchmarks/light_bvh_check.sh's step 3: 7 interleaved pairs, median render ms.
for i in 1 2 3 4 5 6 7; do for s in power bvh; do
  .device/bin/pathtracer scenes/cornell_box.json -o "$OUT/cornell/c_$s.exr" --width 1024 --height 1024 \
    --spp 64 --backend cuda --light-sampler "$s" --quiet --stats-json "$OUT/cornell/cornell_${s}_$i.json"
done; done
