# H100, main 835ef01: the Breakfast Room (sun and sky) at its own 1280x720, 4 seeds, 4096-spp reference.
python3 benchmarks/denoise_curve.py --binary .device/bin/pathtracer --out $OUT/dcb \
  --scenes benchmarks/scenes/breakfast_room_sunsky.json:1280x720 --spps 16,256 --seeds 4 \
  --ref-spp 4096 --label "NVIDIA H100 80GB HBM3, main 835ef01, 4 seeds"
