#!/bin/bash
# CPU (this 2-core AMD EPYC build machine), main at da50400: DamagedHelmet's visor crop at 1080p,
# 16 spp with Sobol samples, 8 seeds, relMSE against 4,096 spp of ours, parted into variance
# across seeds and bias (docs/denoise.md: what the helmet's gap is made of).
/usr/bin/python3 benchmarks/denoise_curve.py --binary build/pathtracer --backend cpu \
  --scenes benchmarks/scenes/damaged_helmet.json:1920x1080 \
  --extra "--sampler sobol --crop 800 380 1120 640" --spps 16 --seeds 8 --ref-spp 4096 --split \
  --variant "sample variance=--denoise-variance sample" \
  --label "CPU, DamagedHelmet visor crop 320x260 of 1080p, Sobol" \
  --out benchmarks/results/denoise_helmet_split_2026-11-28
