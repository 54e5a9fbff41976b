#!/bin/bash
# Render rates of this tree (new) against d3c2fa2 (base, the flat shade copy), 5 interleaved
# rounds, on one warm machine: summary_h100_c8f16f4.txt (accumulate testing the half films at
# run time) and summary_h200_<commit>.txt (compiled both ways) are its output (the per-run
# stats JSON did not all come back from the device).
python3 benchmarks/compare_renders.py --binary base=build_q/base/pathtracer \
  --binary new=build_q/new/pathtracer --rounds 5 --out $OUT/r
