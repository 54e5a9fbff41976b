# Made on the CPU (2 cores, shared with a build) with main at 7ac1e06's build:
/usr/bin/python3 benchmarks/media_accuracy.py --binary build/pathtracer --backend cpu \
  --size 128x72 --ref-spp 2048 --seconds 20 --out /tmp/media_acc
# then error_vs_time.{csv,md,png} copied here (the EXRs and stats stay out).
