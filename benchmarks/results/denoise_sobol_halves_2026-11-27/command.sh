# On the H100 (one device call), .q/new/pathtracer being this tree's pathtracer built for sm_90.
# The binary's default then was --denoise-variance calibrated for both samplers: the columns
# raw/denoised are independent samples with the calibrated variance, "sample" the sample
# variance, "sobol" Sobol with the calibrated variance, "sobol sample" Sobol with the sample
# variance. The committed default: calibrated for Sobol, sample for independent samples.
python3 benchmarks/denoise_curve.py --binary .q/new/pathtracer --out "$OUT/q" --spps 16,256 \
  --seeds 2 --ref-spp 4096 \
  --scenes benchmarks/scenes/bunny_cornell.json:1920x1080,benchmarks/scenes/breakfast_room_sunsky.json:1280x720,benchmarks/scenes/damaged_helmet.json:1920x1080 \
  --variant "sample=--denoise-variance sample" --variant "sobol=--sampler sobol" \
  --variant "sobol sample=--sampler sobol --denoise-variance sample" --variant-raw \
  --label "H100, calibrated variance and Sobol halves"
