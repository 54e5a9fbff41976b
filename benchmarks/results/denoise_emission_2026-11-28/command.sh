#!/bin/bash
# H100 (device call of 2026-11-28), main at c8f16f4 built for sm_90: the denoiser with the seen
# emission kept out (--denoise-emission keep) or filtered (filter), relMSE against 4096 spp of
# ours at the scenes' benchmark sizes. Run from the repository root, P the pathtracer.
S=benchmarks/scenes/bunny_cornell.json:1920x1080,benchmarks/scenes/breakfast_room_sunsky.json:1280x720,benchmarks/scenes/damaged_helmet.json:1920x1080
python3 benchmarks/denoise_curve.py --binary $P --out $OUT/sobol --spps 16 --seeds 4 --ref-spp 4096 \
  --scenes $S --extra "--sampler sobol" --variant "filter=--denoise-emission filter" \
  --label "H100, Sobol samples: seen emission kept out (then the default) or filtered"
python3 benchmarks/denoise_curve.py --binary $P --out $OUT/indep --spps 16,256 --seeds 2 --ref-spp 4096 \
  --scenes $S --extra "--sampler independent" --variant "keep=--denoise-emission keep" \
  --label "H100, independent samples: seen emission filtered (default) or kept out"
