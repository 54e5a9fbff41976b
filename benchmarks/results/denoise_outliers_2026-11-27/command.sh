# H100 (one device call), main + the outlier passes: three scenes at their benchmark sizes,
# 4 seeds, 16 and 256 spp, each film denoised with --denoise-outliers on (the default) and off;
# relMSE against 4096 spp of ours (its own noise taken out). Then the denoiser's time.
python3 benchmarks/denoise_curve.py --binary .device/bin/pathtracer --out $OUT/dq \
  --scenes benchmarks/scenes/bunny_cornell.json:1920x1080,benchmarks/scenes/breakfast_room_sunsky.json:1280x720,benchmarks/scenes/damaged_helmet.json:1920x1080 \
  --spps 16,256 --seeds 4 --ref-spp 4096 --outliers-off-too --label "H100, main + outlier passes, 4 seeds"
STEPS=time bash benchmarks/denoise_check.sh
