# H100 (nvidia-h100-x1), main 835ef01 packed by tools/pack_device.sh; 2 seeds per spp,
# references of 8192 spp of ours. Plot made here afterwards with --plot.
python3 benchmarks/denoise_curve.py --binary .device/bin/pathtracer --out $OUT/dc \
  --label "NVIDIA H100 80GB HBM3, main 835ef01"
/usr/bin/python3 benchmarks/denoise_curve.py --plot benchmarks/results/denoise_curve_2026-11-27/denoise_curve.csv
